#pragma once
// Names for cached renders (the sweep's reference, the modules' truth
// references): a hash of everything the file depends on, the build included,
// so a stale file is never read.
#include <cstdint>
#include <string>

namespace cr {

// FNV-1a over the bytes, continuing from `h`.
uint64_t fnv1a(const std::string& bytes, uint64_t h = 0xcbf29ce484222325ull);
// 16 hex digits of fnv1a(key): a file name.
std::string cache_name(const std::string& key);
// The hash of the running executable's bytes (computed once): another build
// may render differently.
const std::string& build_hash();

}  // namespace cr
