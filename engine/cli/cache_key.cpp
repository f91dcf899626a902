#include "engine/cli/cache_key.h"

#include <cstdio>

#include "engine/output/atomic_file.h"

namespace cr {

uint64_t fnv1a(const std::string& bytes, uint64_t h) {
  for (unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ull;
  return h;
}

std::string cache_name(const std::string& key) {
  char name[32];
  std::snprintf(name, sizeof name, "%016llx", static_cast<unsigned long long>(fnv1a(key)));
  return name;
}

const std::string& build_hash() {
  static const std::string hash = std::to_string(fnv1a(read_file_bytes("/proc/self/exe")));
  return hash;
}

}  // namespace cr
