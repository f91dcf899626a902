// The run's memory budget: charges add up, a charge over the limit is refused
// with the file, field, estimate and limit and leaves the total unchanged;
// sizes parse with binary units and never wrap.
#include <doctest/doctest.h>

#include <cstdint>
#include <limits>
#include <string>

#include "engine/core/error.h"
#include "engine/core/memory_budget.h"

TEST_CASE("memory budget: charges add up and one over the limit is refused, naming file, field and sizes") {
  cr::MemoryBudget b(size_t(100) << 20);
  b.charge("frame buffers", "p.json", "resolution", size_t(60) << 20);
  CHECK(b.total() == size_t(60) << 20);
  try {
    b.charge("froxel grid", "p.json", "fog.froxel_size_px", size_t(50) << 20);
    FAIL_CHECK("a charge beyond the limit was accepted");
  } catch (const cr::InputError& e) {
    CHECK(e.file() == "p.json");
    CHECK(std::string(e.what()) ==
          "p.json: fog.froxel_size_px (froxel grid) needs 50.0 MiB, on top of 60.0 MiB already estimated, beyond the "
          "memory limit of 100.0 MiB (lower it in the file, or raise the limit with --memory-limit)");
  }
  CHECK(b.total() == size_t(60) << 20);  // the refused charge is not recorded
  CHECK(b.charges().size() == 1);
  CHECK_NOTHROW(b.charge("rest", "p.json", "x", size_t(40) << 20));  // exactly the limit fits
  CHECK_THROWS_AS(b.require("one byte", "p.json", "x", 1), cr::InputError);
}

TEST_CASE("memory budget: a limit of 0 is none, and sums saturate instead of wrapping") {
  cr::MemoryBudget b(0);
  b.charge("a", "f", "x", std::numeric_limits<size_t>::max());
  b.charge("b", "f", "y", 5);
  CHECK(b.total() == std::numeric_limits<size_t>::max());
  CHECK(cr::saturating_product({size_t(1) << 40, size_t(1) << 40}) == std::numeric_limits<size_t>::max());
  CHECK(cr::saturating_product({16384, 16384, 4}) == size_t(1) << 30);
  CHECK(cr::saturating_product({std::numeric_limits<size_t>::max(), 0}) == 0);
  cr::MemoryBudget limited(size_t(1) << 30);
  CHECK_THROWS_AS(limited.charge("huge", "f", "x", cr::saturating_product({size_t(1) << 40, size_t(1) << 40})),
                  cr::InputError);
}

TEST_CASE("memory budget: sizes parse with units, malformed or overflowing ones are rejected") {
  size_t v = 0;
  CHECK((cr::MemoryBudget::parse_size("4G", v) && v == size_t(4) << 30));
  CHECK((cr::MemoryBudget::parse_size("512M", v) && v == size_t(512) << 20));
  CHECK((cr::MemoryBudget::parse_size("100k", v) && v == 102400));
  CHECK((cr::MemoryBudget::parse_size("2GiB", v) && v == size_t(2) << 30));
  CHECK((cr::MemoryBudget::parse_size("123", v) && v == 123));
  CHECK((cr::MemoryBudget::parse_size("0", v) && v == 0));
  for (const char* bad : {"", "12x", "-1", "G", "1.5G", " 1G", "1G ", "99999999999999999999", "99999999999G"})
    CHECK_MESSAGE(!cr::MemoryBudget::parse_size(bad, v), bad);
}

TEST_CASE("memory budget: the default limit is half of the machine's memory at most, and sizes print readably") {
  CHECK(cr::MemoryBudget::default_limit() > size_t(64) << 20);
  CHECK(cr::MemoryBudget::format_bytes(17) == "17 bytes");
  CHECK(cr::MemoryBudget::format_bytes(640 << 10) == "640 KiB");
  CHECK(cr::MemoryBudget::format_bytes(size_t(12) << 20) == "12.0 MiB");
  CHECK(cr::MemoryBudget::format_bytes(size_t(3) << 29) == "1.50 GiB");
}
