#include "fog/tools/fog_truth.h"

#include <cstdio>
#include <filesystem>

#include "engine/cli/cache_key.h"
#include "engine/core/error.h"
#include "engine/output/atomic_file.h"
#include "engine/output/exr_io.h"
#include "engine/render/frame_view.h"
#include "fog/tools/fog_accuracy.h"

namespace cr {

namespace {

const char* const kModule = "fog";

// The reference's fog (in-scattered light R, G, B and transmittance T), in float.
void write_fog_reference(const std::string& path, const FogReferenceImage& ref) {
  std::vector<ExrChannel> channels;
  for (int c = 0; c < 4; ++c) channels.push_back({std::string(1, "RGBT"[c]), ExrPixelType::Float, {}});
  for (size_t i = 0; i < ref.transmittance.size(); ++i) {
    for (int c = 0; c < 3; ++c) channels[size_t(c)].values.push_back(ref.in_scatter[i][c]);
    channels[3].values.push_back(ref.transmittance[i]);
  }
  write_exr_channels(path, ref.width, ref.height, channels);
}

FogReferenceImage read_fog_reference(const std::string& path) {
  const ExrImage img = read_exr(path);
  FogReferenceImage ref;
  ref.width = img.color.width;
  ref.height = img.color.height;
  for (size_t i = 0; i < img.color.rgb.size() / 3; ++i)
    ref.in_scatter.emplace_back(img.color.rgb[3 * i], img.color.rgb[3 * i + 1], img.color.rgb[3 * i + 2]);
  for (const ExrChannel& c : img.aovs)
    if (c.name == "T") ref.transmittance = c.values;
  if (ref.transmittance.size() != ref.in_scatter.size()) throw InputError(path, "channel T: missing or of another size");
  return ref;
}

std::optional<ModuleTruthResult> measure_fog_truth(const ModuleTruthRequest& r, const PluginRegistry& plugins) {
  if (!r.description.plugins.contains(kModule) || orthographic_view(r.scene, r.description)) return std::nullopt;
  if (!has_fog_media(parse_fog_scene(r.description.plugins.at(kModule), r.description.path))) return std::nullopt;
  const int samples = r.settings.at("samples").get<int>(), warmup = r.settings.at("warmup").get<int>();
  const int max_width = r.settings.at("max_width").get<int>();
  // At most max_width wide: the point's size divided by a whole factor k, and its froxels k times
  // smaller in pixels, so the grid keeps the point's froxel count (the method's error is the point's).
  // At the output size: the fog tools composite over output-size buffers (render_scale is not measured).
  const int k = (r.width + max_width - 1) / max_width;
  Profile profile = r.profile;
  profile.render_scale = 1.0f;
  profile.width = std::max(1, (r.width + k / 2) / k);
  profile.height = std::max(1, (r.height + k / 2) / k);
  // The scene is the sweep's, posed at the measured frame; the run does not own it.
  FogRun run = make_fog_run(r.description, std::move(profile),
                            std::shared_ptr<const Scene>(std::shared_ptr<const Scene>(), &r.scene));
  run.fog_profile.froxel_size_px = std::max(1, (run.fog_profile.froxel_size_px + k / 2) / k);
  JobSystem jobs(r.threads);
  Renderer base(*run.scene, run.description, run.profile, plugins_without_fog(plugins), jobs);
  base.render_frame(r.frame);
  const FrameView view = base.frame_view(r.frame);

  // The reference sees the base frame, which does not depend on the profile's fog section but its range.
  nlohmann::json base_profile = r.profile_document;
  base_profile.erase(kModule);
  char key[96];
  std::snprintf(key, sizeof key, "|%dx%d|%d|%d|%.9g", run.profile.width, run.profile.height, r.frame, samples,
                double(run.fog_profile.fog_distance));
  const std::string path = r.cache_dir + "/" +
                           cache_name(std::string("fog truth|") + r.build_hash + "|" + r.description.path + "|" +
                                      read_file_bytes(r.description.path) + "|" + base_profile.dump() + key) +
                           ".fog.exr";
  ModuleTruthResult result;
  result.reference_cached = std::filesystem::exists(path);
  FogReferenceImage ref;
  if (result.reference_cached) {
    ref = read_fog_reference(path);
  } else {
    ref = render_fog_reference(run, base, view, samples, jobs);
    write_fog_reference(path, ref);
  }
  std::vector<glm::vec3> image;
  const FogAccuracyRow row = measure_froxel_config(run, base, view, jobs, temporal_config(run.fog_profile, warmup),
                                                   fog_reference_composite(base, ref), image);
  result.rel_luminance_mean = row.error.mean;
  result.rel_luminance_p95 = row.error.p95;
  // A deterministic quadrature: no Monte-Carlo noise to report.
  result.reference = "per-pixel ray-marched fog, " + std::to_string(samples) + " samples, " +
                     std::to_string(run.profile.width) + "x" + std::to_string(run.profile.height) +
                     ", temporal grid after " + std::to_string(temporal_config(run.fog_profile, warmup).frames - 1) +
                     " frames of history";
  return result;
}

}  // namespace

ModuleTruth fog_truth(const PluginRegistry& plugins) {
  // 128 samples: the temporal error moves by under 1% of itself against 512 (fog_valley_flythrough, 320x180).
  // 320 wide: a point costs about 0.2 s, 0.8-1 s where it renders its reference (two cores).
  // warmup 14: fog-accuracy's default, two cycles of the 7-frame jitter.
  return {kModule,
          {{"samples", 128, 1, 65536}, {"warmup", 14, 0, 1000}, {"max_width", 320, 16, 16384}},
          [&plugins](const ModuleTruthRequest& r) { return measure_fog_truth(r, plugins); }};
}

}  // namespace cr
