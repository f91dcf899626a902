#include <doctest/doctest.h>

#include <cstring>
#include <vector>

#include "fog/volume_shadow.h"
#include "fog_test_scene.h"

using namespace cr;
using namespace cr::fog_test;

// The batch lookup (AVX2 gathers where the CPU has them) must give the bits of
// the one-point lookup: on rays that cross the wall's shadow edge, leave the
// map sideways, and run past its depth range, with odd counts for the tail.
TEST_CASE("batched shadow lookups are bit-identical to single lookups") {
  const Camera cam = camera_at({-3, 2, 10}, {0, 2, -10}, 160, 90);
  const glm::vec3 sun(0.6f, 0.4f, 0.3f);
  const ShadowMap map = wall_shadow(cam, sun);
  const VolumeShadow shadow(map, cam.position);
  REQUIRE_FALSE(shadow.empty());
  std::vector<float> t, batch, single;
  size_t shadowed = 0, lit = 0, partial = 0;
  for (int r = 0; r < 64; ++r) {
    const float a = float(r) * 0.1f;
    const glm::vec3 dir = glm::normalize(glm::vec3(std::cos(a), 0.2f * std::sin(3.0f * a) - 0.05f, -std::sin(a)));
    const VolumeShadow::Ray ray = shadow.ray(glm::vec3(0.3f * float(r % 5), 0.0f, 0.0f), dir);
    const int n = 3 + r * 7 % 61;
    t.resize(size_t(n));
    for (int k = 0; k < n; ++k) t[size_t(k)] = 0.05f + 1000.0f * float(k * k) / float(n * n);
    batch.assign(size_t(n), -1.0f);
    single.resize(size_t(n));
    shadow.visibility(ray, t.data(), n, batch.data());
    for (int k = 0; k < n; ++k) {
      single[size_t(k)] = shadow.visibility(ray, t[size_t(k)]);
      const float v = single[size_t(k)];
      shadowed += v == 0.0f;
      lit += v == 1.0f;
      partial += v > 0.0f && v < 1.0f;
    }
    CHECK(std::memcmp(batch.data(), single.data(), single.size() * sizeof(float)) == 0);
  }
  // The rays really exercise all three cases.
  CHECK(shadowed > 0);
  CHECK(lit > 0);
  CHECK(partial > 0);
}
