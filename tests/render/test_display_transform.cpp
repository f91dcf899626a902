// The table-driven display transform equals the per-pixel definition.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "engine/core/hdr16.h"
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

TEST_CASE("display transform resolve() of a pixel row equals encode() at every code step") {
  // resolve() is a vectorised loop over the channels as flat floats: check it
  // against the scalar encode() (checked against resolve_pixel above) on
  // radiances right at and next to each step of the code (found by bisection
  // on the definition), a sweep past both ends of the table and the special
  // values, in a row whose length leaves a tail after the vector loop.
  const float ev = 10.0f;
  cr::DisplayTransform t(ev);
  const float exposure = cr::exposure_scale(ev);
  auto reference = [&](float radiance) {
    uint8_t rgb[3];
    cr::resolve_pixel(glm::vec3(radiance), exposure, rgb);
    return int(rgb[0]);
  };
  std::vector<float> values = {0.0f, -0.0f, -1.0f, std::numeric_limits<float>::infinity(),
                               -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(),
                               -std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::denorm_min(),
                               std::numeric_limits<float>::max(), -std::numeric_limits<float>::max()};
  const uint32_t first = std::bit_cast<uint32_t>(std::ldexp(1.0f, -26) / exposure);
  const uint32_t last = std::bit_cast<uint32_t>(std::ldexp(1.0f, 7) / exposure);
  const uint32_t stride = 997;
  int steps = 0;
  for (uint32_t bits = first; bits < last; bits += stride) {
    values.push_back(std::bit_cast<float>(bits));
    if (reference(std::bit_cast<float>(bits)) == reference(std::bit_cast<float>(bits + stride))) continue;
    uint32_t lo = bits, hi = bits + stride;  // code(lo) < code(hi): find the first bits with code(hi)
    while (hi - lo > 1) {
      const uint32_t mid = lo + (hi - lo) / 2;
      (reference(std::bit_cast<float>(mid)) > reference(std::bit_cast<float>(lo)) ? hi : lo) = mid;
    }
    for (uint32_t b : {hi - 1, hi, hi + 1}) values.push_back(std::bit_cast<float>(b));
    ++steps;
  }
  CHECK(steps == 255);
  while (values.size() % 3 != 0 || values.size() % 32 == 0) values.push_back(1.0f);
  const size_t count = values.size() / 3;
  std::vector<glm::vec3> hdr(count);
  std::memcpy(hdr.data(), values.data(), values.size() * sizeof(float));
  std::vector<uint8_t> out(3 * count + 1, 0xab);  // one guard byte
  t.resolve(hdr.data(), count, out.data());
  for (size_t i = 0; i < values.size(); ++i) REQUIRE(int(out[i]) == int(t.encode(values[i])));
  CHECK(out[3 * count] == 0xab);
}

TEST_CASE("fixed-point resolve: the table is encode() of every hdr16 code, and codes differ by at most one near steps") {
  for (float ev100 : {-6.0f, 0.0f, 12.0f, 15.0f}) {
    CAPTURE(ev100);
    const cr::DisplayTransform display(ev100);
    const cr::Hdr16Display fixed(display);
    for (uint32_t code = 0; code < 65536; code += 7)
      CHECK(fixed.encode(cr::fx::decode_hdr16(uint16_t(code))) == display.encode(cr::fx::decode_hdr16(uint16_t(code))));
    // A dense geometric sweep over the displayed range (and beyond it both ways).
    const float white = 1.2f * std::exp2(ev100);
    size_t differing = 0, n = 0;
    std::vector<glm::vec3> hdr;
    for (float v = white * 1e-6f; v < white * 1e3f; v *= 1.0007f) hdr.push_back(glm::vec3(v, 0.5f * v, 2.0f * v));
    std::vector<uint8_t> a(3 * hdr.size()), b(3 * hdr.size());
    display.resolve(hdr.data(), hdr.size(), a.data());
    fixed.resolve(hdr.data(), hdr.size(), b.data());
    for (size_t i = 0; i < a.size(); ++i, ++n) {
      CHECK(std::abs(int(a[i]) - int(b[i])) <= 1);
      differing += a[i] != b[i] ? 1 : 0;
    }
    MESSAGE("EV100 " << ev100 << ": " << differing << " of " << n << " codes differ from the float resolve");
    CHECK(double(differing) < 0.01 * double(n));  // only values within 2^-11 of a step
    // Specials: NaN, negative and infinity as the float resolve treats them.
    for (float v : {std::numeric_limits<float>::quiet_NaN(), -1.0f, 0.0f, std::numeric_limits<float>::infinity()})
      CHECK(fixed.encode(v) == display.encode(v));
  }
}
