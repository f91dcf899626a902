#include "engine/core/memory_budget.h"

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <limits>

#include "engine/core/error.h"

namespace cr {

namespace {

size_t saturating_add(size_t a, size_t b) {
  return a > std::numeric_limits<size_t>::max() - b ? std::numeric_limits<size_t>::max() : a + b;
}

// cgroup v2 memory.max ("max" or bytes); SIZE_MAX where there is none.
size_t cgroup_limit() {
  std::ifstream f("/sys/fs/cgroup/memory.max");
  std::string s;
  if (!(f >> s) || s == "max") return std::numeric_limits<size_t>::max();
  size_t v = 0;
  return MemoryBudget::parse_size(s, v) && v > 0 ? v : std::numeric_limits<size_t>::max();
}

}  // namespace

size_t saturating_product(std::initializer_list<size_t> factors) {
  size_t p = 1;
  for (size_t f : factors) {
    if (f == 0) return 0;
    if (p > std::numeric_limits<size_t>::max() / f) p = std::numeric_limits<size_t>::max();
    else p *= f;
  }
  return p;
}

void MemoryBudget::require(const std::string& what, const std::string& file, const std::string& field,
                           size_t bytes) const {
  if (limit_ == 0 || saturating_add(total_, bytes) <= limit_) return;
  std::string msg = field.empty() ? what : field + " (" + what + ")";
  msg += " needs " + format_bytes(bytes);
  if (total_ > 0) msg += ", on top of " + format_bytes(total_) + " already estimated,";
  msg += " beyond the memory limit of " + format_bytes(limit_) +
         " (lower it in the file, or raise the limit with --memory-limit)";
  throw InputError(file, msg);
}

void MemoryBudget::charge(const std::string& what, const std::string& file, const std::string& field,
                          size_t bytes) {
  require(what, file, field, bytes);
  total_ = saturating_add(total_, bytes);
  charges_.push_back({what, file, field, bytes});
}

size_t MemoryBudget::default_limit() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  size_t physical = pages > 0 && page > 0 ? size_t(pages) * size_t(page) : size_t(8) << 30;
  const size_t cgroup = cgroup_limit();
  if (cgroup < physical) physical = cgroup;
  return physical / 2;
}

std::string MemoryBudget::format_bytes(size_t bytes) {
  char buf[64];
  const double b = double(bytes);
  if (bytes >= (size_t(1) << 30)) std::snprintf(buf, sizeof buf, "%.2f GiB", b / double(1 << 30));
  else if (bytes >= (size_t(1) << 20)) std::snprintf(buf, sizeof buf, "%.1f MiB", b / double(1 << 20));
  else if (bytes >= (size_t(1) << 10)) std::snprintf(buf, sizeof buf, "%.0f KiB", b / double(1 << 10));
  else std::snprintf(buf, sizeof buf, "%zu bytes", bytes);
  return buf;
}

bool MemoryBudget::parse_size(const std::string& text, size_t& bytes) {
  if (text.empty() || text.size() > 24) return false;
  size_t i = 0;
  uint64_t v = 0;
  for (; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i) {
    if (v > (std::numeric_limits<uint64_t>::max() - 9) / 10) return false;
    v = v * 10 + uint64_t(text[i] - '0');
  }
  if (i == 0) return false;
  int shift = 0;
  if (i < text.size()) {
    const std::string unit = text.substr(i);
    if (unit == "k" || unit == "K" || unit == "KiB") shift = 10;
    else if (unit == "m" || unit == "M" || unit == "MiB") shift = 20;
    else if (unit == "g" || unit == "G" || unit == "GiB") shift = 30;
    else if (unit == "t" || unit == "T" || unit == "TiB") shift = 40;
    else return false;
  }
  if (shift && v > (std::numeric_limits<uint64_t>::max() >> shift)) return false;
  bytes = size_t(v << shift);
  return true;
}

}  // namespace cr
