#include <doctest/doctest.h>

#include <cstring>

#include "fog_test_scene.h"

using namespace cr;
using namespace cr::fog_test;

namespace {

// The volume's bytes, either precision.
std::vector<unsigned char> volume_bytes(const FroxelFog& fog) {
  const unsigned char* begin = fog.fixed_point() ? reinterpret_cast<const unsigned char*>(fog.fixed_volume().data())
                                                 : reinterpret_cast<const unsigned char*>(fog.volume().data());
  const size_t bytes = fog.fixed_point() ? fog.fixed_volume().size() * sizeof(FixedIntegratedFroxel)
                                         : fog.volume().size() * sizeof(IntegratedFroxel);
  return std::vector<unsigned char>(begin, begin + bytes);
}

}  // namespace

TEST_CASE("froxel fog is bit-identical for 1, 2 and 3 threads, at either precision") {
  const int w = 80, h = 48;
  const FogSceneSettings s = noisy_volume_fog();
  const glm::vec3 sun(0.6f, 0.4f, 0.3f);
  for (FogPrecision precision : {FogPrecision::Float, FogPrecision::Fixed}) {
    CAPTURE(precision);
    std::vector<std::vector<unsigned char>> volumes;
    std::vector<std::vector<glm::vec3>> images;
    for (unsigned threads : {1u, 2u, 3u}) {
      JobSystem jobs(threads);
      FogProfileSettings p;
      p.slices = 24;
      p.precision = precision;
      FroxelFog fog(p, s);
      Camera prev;
      std::vector<glm::vec3> image;
      std::vector<float> distance(size_t(w) * h);
      for (size_t i = 0; i < distance.size(); ++i) distance[i] = i % 3 == 0 ? INFINITY : 2.0f + float(i % 50);
      // Two moving frames, then still ones (the still mean and incremental integration).
      for (int f = 0; f < 5; ++f) {
        const Camera cam = camera_at({-3.0 + std::min(f, 2), 2, 10}, {0, 2, -10}, w, h);
        image = composite(fog, frame_view(cam, f ? prev : cam, f, f > 0, w, h), light(sun, 5e4f, 100.0f),
                          wall_shadow(cam, sun), jobs, distance, glm::vec3(1.0f));
        prev = cam;
      }
      volumes.push_back(volume_bytes(fog));
      images.push_back(image);
    }
    REQUIRE(!volumes[0].empty());
    for (size_t t = 1; t < volumes.size(); ++t) {
      CHECK(volumes[t] == volumes[0]);
      CHECK(std::memcmp(images[t].data(), images[0].data(), images[0].size() * sizeof(glm::vec3)) == 0);
    }
  }
}
