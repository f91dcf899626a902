// The fixed-point fog's error per froxel against the float fog (docs/fog.md,
// "Reduced precision (mobile)"): both precisions run side by side over the
// same frames of a synthetic view (640x360, a wall's shaft under a low sun in
// front of the camera, 6 moving frames then 10 still), and the in-scatter
// luminance's relative error, the transmittance's relative error and the
// visibility's absolute error are summarised over every froxel.
//   build/tests/bench_fog_precision_error [volumes]
// With "volumes", the fog is height fog with a noisy box volume instead of
// the valley's height fog (mean free path 90 m up to 20 m, Cornette-Shanks 0.6).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "fog/fog_test_scene.h"

using namespace cr;
using namespace cr::fog_test;

namespace {

void summarise(const char* name, std::vector<double> v) {
  std::sort(v.begin(), v.end());
  double mean = 0.0;
  for (double x : v) mean += x;
  mean /= double(v.size());
  std::printf("%-30s mean %.2e  p50 %.2e  p95 %.2e  p99 %.2e  largest %.2e  (%zu froxels)\n", name, mean,
              v[v.size() / 2], v[v.size() * 95 / 100], v[v.size() * 99 / 100], v.back(), v.size());
}

}  // namespace

int main(int argc, char** argv) {
  const int w = 640, h = 360;
  JobSystem jobs(2);
  FogSceneSettings s = uniform_fog(1.0f / 90.0f, glm::vec3(0.95f), 0.6f);
  s.phase = FogPhase::CornetteShanks;
  s.base_height = 0.0f;
  s.max_height = 20.0f;
  s.distance = 128.0f;
  if (argc > 1 && std::strcmp(argv[1], "volumes") == 0) s = noisy_volume_fog();
  FogProfileSettings in_float;
  FogProfileSettings in_fixed = in_float;
  in_fixed.precision = FogPrecision::Fixed;
  FroxelFog float_fog(in_float, s), fixed_fog(in_fixed, s);
  const glm::vec3 sun(0.35f, 0.12f, -0.9f);
  const std::vector<float> distance(size_t(w) * h, INFINITY);
  Camera prev;
  for (int f = 0; f < 16; ++f) {
    const Camera cam = camera_at({-2.0 + 0.5 * std::min(f, 5), 2, 8}, {0, 1.5, -20}, w, h);
    const ShadowMap shadow = wall_shadow(cam, sun);
    for (FroxelFog* fog : {&float_fog, &fixed_fog})
      fog->render(frame_view(cam, f ? prev : cam, f, f > 0, w, h), light(sun, 1e5f, 2000.0f), shadow, jobs, &distance);
    prev = cam;
  }
  std::vector<double> in_scatter, transmittance, visibility;
  for (size_t i = 0; i < float_fog.volume().size(); ++i) {
    const IntegratedFroxel a = float_fog.volume()[i], b = fixed_fog.integrated_froxel(i);
    const double la = luminance(glm::dvec3(a.in_scatter)), lb = luminance(glm::dvec3(b.in_scatter));
    if (la > 0.0) in_scatter.push_back(std::abs(lb - la) / la);
    if (a.transmittance > 1e-6f) transmittance.push_back(std::abs(double(b.transmittance) - a.transmittance) / a.transmittance);
    visibility.push_back(std::abs(double(float_fog.sun_visibility()[i]) - fx::decode_q15(fixed_fog.sun_visibility_q15()[i])));
  }
  summarise("in-scatter, relative", in_scatter);
  summarise("transmittance, relative", transmittance);
  summarise("visibility, absolute", visibility);
  return 0;
}
