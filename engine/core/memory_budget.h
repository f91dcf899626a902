#pragma once
// The memory a run may use, checked before anything large is allocated. Each
// part of a run (decoded textures, frame buffers, shadow map, LUTs, froxel
// grids) charges its estimate, in bytes, with the file and field that decide
// it; a charge that takes the total over the limit throws an InputError that
// names that file and field, the estimate, the total and the limit. So an
// input that asks for too much is refused at load, never as std::bad_alloc.
#include <cstddef>
#include <initializer_list>
#include <string>
#include <vector>

namespace cr {

class MemoryBudget {
 public:
  struct Charge {
    std::string what;   // e.g. "image 3 (4096x4096 RGBA8 with mips)"
    std::string file;
    std::string field;  // e.g. "images[3]", "atmosphere.sky_view_lut.width"
    size_t bytes = 0;
  };

  // `limit_bytes` 0 means unlimited (charges are still recorded).
  explicit MemoryBudget(size_t limit_bytes = default_limit()) : limit_(limit_bytes) {}

  // Adds `bytes`; throws InputError(file, ...) when the total would exceed the limit.
  void charge(const std::string& what, const std::string& file, const std::string& field, size_t bytes);
  // The same check without recording (e.g. one image before it is decoded).
  void require(const std::string& what, const std::string& file, const std::string& field, size_t bytes) const;

  size_t limit() const { return limit_; }
  size_t total() const { return total_; }
  const std::vector<Charge>& charges() const { return charges_; }

  // Half of the machine's physical memory, or of the cgroup's limit where
  // that is lower: room for the OS and for what estimates leave out.
  static size_t default_limit();
  // "1.50 GiB", "12.0 MiB", "640 KiB", "17 bytes".
  static std::string format_bytes(size_t bytes);
  // "4G", "512M", "100k", "1073741824" (bytes); 0 = unlimited. UsageError-free:
  // returns false on a malformed or out-of-range value.
  static bool parse_size(const std::string& text, size_t& bytes);

 private:
  size_t limit_;
  size_t total_ = 0;
  std::vector<Charge> charges_;
};

// a * b * ... saturating at SIZE_MAX, for estimates from untrusted sizes.
size_t saturating_product(std::initializer_list<size_t> factors);

}  // namespace cr
