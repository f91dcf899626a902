// The table-driven display transform equals the per-pixel definition.
#include <doctest/doctest.h>

#include <bit>
#include <cstdint>
#include <limits>
#include <random>

#include "engine/render/display_transform.h"
#include "engine/shading/tonemap.h"

TEST_CASE("display transform table matches resolve_pixel exactly") {
  for (float ev : {0.0f, 10.0f, 15.0f}) {
    cr::DisplayTransform t(ev);
    const float exposure = cr::exposure_scale(ev);
    std::mt19937 rng(42);
    std::uniform_real_distribution<float> log_value(-12.0f, 8.0f);
    auto check = [&](float radiance) {
      uint8_t ref[3];
      cr::resolve_pixel(glm::vec3(radiance), exposure, ref);
      REQUIRE(int(t.encode(radiance)) == int(ref[0]));
    };
    for (int i = 0; i < 200000; ++i) check(std::pow(10.0f, log_value(rng)) / exposure);
    // Exactly at and next to every threshold of the step function.
    for (int k = 0; k < 200000; ++k) {
      const float e = float(k) / 200000.0f * 8.0f;
      check(e / exposure);
    }
    for (float special : {0.0f, -1.0f, std::numeric_limits<float>::infinity(),
                          std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::denorm_min(),
                          std::numeric_limits<float>::max()})
      check(special);
  }
}

TEST_CASE("display transform table matches resolve_pixel across every bucket of exposed values") {
  // Exposed values from 2^-25 to 2^6 (past both ends of the table) at every
  // 4099th float: each float-bits bucket (8192 wide) is met about twice, at
  // offsets from its start that drift across it.
  const float ev = 15.0f;
  cr::DisplayTransform t(ev);
  const float exposure = cr::exposure_scale(ev);
  for (uint32_t bits = uint32_t(127 - 25) << 23; bits < uint32_t(127 + 6) << 23; bits += 4096 + 3) {
    const float radiance = std::bit_cast<float>(bits) / exposure;
    uint8_t ref[3];
    cr::resolve_pixel(glm::vec3(radiance), exposure, ref);
    REQUIRE(int(t.encode(radiance)) == int(ref[0]));
  }
}

TEST_CASE("display transform codes are monotone in radiance") {
  cr::DisplayTransform t(15.0f);
  int last = 0;
  for (float r = 1.0f; r < 1e7f; r *= 1.01f) {
    const int c = t.encode(r);
    CHECK(c >= last);
    last = c;
  }
  CHECK(last == 255);
}
