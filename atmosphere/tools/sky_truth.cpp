#include "atmosphere/tools/sky_truth.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "atmosphere/spectral_sampling.h"
#include "atmosphere/tools/accuracy_score.h"
#include "atmosphere/tools/reference_exr.h"
#include "atmosphere/tools/sky_accuracy_case.h"
#include "engine/cli/cache_key.h"
#include "engine/render/frame_view.h"

namespace cr {

namespace {

const char* const kModule = "atmosphere";

std::optional<ModuleTruthResult> measure_sky_truth(const ModuleTruthRequest& r) {
  // No atmosphere section, or an orthographic view: the scene has no sky passes.
  if (!r.description.plugins.contains(kModule) || orthographic_view(r.scene, r.description)) return std::nullopt;
  const int w = r.settings.at("panorama_width").get<int>(), h = r.settings.at("panorama_height").get<int>();
  ReferenceSettings rs;
  rs.samples_per_pixel = r.settings.at("paths").get<int>();
  rs.seed = r.settings.at("seed").get<uint64_t>();
  rs.sampling = reference_sampling();
  SkySetup setup;
  setup.scene = parse_atmosphere_scene(r.description.plugins.at(kModule), r.description.path);
  setup.settings = parse_atmosphere_settings(
      r.profile.plugins.contains(kModule) ? r.profile.plugins.at(kModule) : nlohmann::json(), r.profile.path);

  // The sky depends on the sun's zenith angle only: the panorama's azimuths start at the sun's.
  const FrameView view = make_frame_view(r.scene, r.description, r.frame, r.width, r.height);
  const double altitude = std::max(0.0, view.camera.position.y);
  const double zenith = glm::degrees(std::acos(double(std::clamp(view.sun_direction.y, -1.0f, 1.0f))));
  const glm::vec3 sun = sun_at_zenith_angle(zenith);
  JobSystem jobs(r.threads);
  const SkyLutPanorama lut = render_lut_panorama(setup, setup.settings, altitude, sun, w, h, jobs);

  // The reference depends on the atmosphere, the view and its own settings, not on the point's profile.
  char view_key[96];
  std::snprintf(view_key, sizeof view_key, "|%.17g|%.17g|%dx%d|%d|%llu", zenith, altitude, w, h,
                rs.samples_per_pixel, static_cast<unsigned long long>(rs.seed));
  const std::string path = r.cache_dir + "/" +
                           cache_name(std::string("atmosphere truth|") + r.build_hash + "|" +
                                      r.description.plugins.at(kModule).dump() + view_key) +
                           ".sky.exr";
  ModuleTruthResult result;
  ReferenceLuminance ref;
  result.reference_cached = std::filesystem::exists(path);
  if (result.reference_cached) {
    read_reference_exr(path, w, h, true, ref);
  } else {
    const ReferenceImage image = render_reference(lut.sky.frame.model, reference_panorama_view(setup, lut, altitude, sun),
                                                  rs, jobs, {});
    ref = reference_luminance(image);
    write_reference_exr(path, image.radiance, ref.luminance, ref.noise, image.ratio_noise, true, w, h);
  }
  const AccuracyScore s = score_accuracy(luminances(lut.radiance), ref.luminance, ref.noise, lut.scored());
  result.rel_luminance_mean = s.mean;
  result.rel_luminance_p95 = s.p95;
  result.noise = s.noise_mean;
  result.reference = "path-traced spectral sky, " + std::to_string(rs.samples_per_pixel) + " paths, " +
                     std::to_string(w) + "x" + std::to_string(h) + " panorama";
  return result;
}

}  // namespace

ModuleTruth sky_truth() {
  // Few directions, many paths: noise raises a mean relative error, more pixels do not average it away.
  // 4096 paths over 16x8 directions: 5-10 s on two cores (longer at a low sun), once per sun and altitude
  // (cached); the reference's mean relative noise is then about 1%.
  return {kModule,
          {{"panorama_width", 16, 2, 1024}, {"panorama_height", 8, 2, 1024}, {"paths", 4096, 1, 1 << 20},
           {"seed", 1, 0, 1 << 30}},
          measure_sky_truth};
}

}  // namespace cr
