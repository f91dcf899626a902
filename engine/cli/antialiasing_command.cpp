// `cpurender aa-error`: what each anti-aliasing mode buys and costs. The
// reference is the same frame rendered at K x K times the resolution without
// anti-aliasing (K = 4: 16 samples per pixel on an ordered grid, each shaded
// and composited on its own), box-filtered in linear radiance and then put
// through the display transform, the resolve every mode uses. Error: the
// 8-bit display codes' mean absolute difference per pixel (mean of RGB), its
// mean and p95 over the edge pixels (those whose K x K reference samples see
// more than one draw, or a draw and nothing) and its mean over all pixels.
// Cost: each pass's median over the frames after two warm-up frames, modes
// interleaved round by round, at 1 and 2 threads.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "engine/cli/arg_parser.h"
#include "engine/cli/cli_common.h"
#include "engine/core/error.h"
#include "engine/output/percentile.h"
#include "engine/raster/raster_types.h"
#include "engine/render/display_transform.h"

namespace cr {

namespace {

struct Mode {
  std::string name;
  int samples = 1;
};

Mode parse_mode(const std::string& name) {
  if (name == "none") return {name, 1};
  if (name == "msaa2" || name == "msaa4" || name == "msaa8") return {name, name[4] - '0'};
  throw UsageError("aa-error: unknown mode '" + name + "' (none, msaa2, msaa4, msaa8)");
}

// Renders frames 0..last of the setup's scene under `profile`; returns the renderer's last frame.
struct Rendered {
  std::vector<glm::vec3> color;
  std::vector<uint8_t> display;
  std::vector<int32_t> draws;
};

Rendered render_last(const RunSetup& setup, const Profile& profile, unsigned threads, int last,
                     const PluginRegistry& registry) {
  JobSystem jobs(threads);
  Renderer renderer(*setup.scene, setup.description, profile, registry.create_all(), jobs);
  attach_playback(renderer, setup);
  for (int f = 0; f <= last; ++f) renderer.render_frame(f);
  return {renderer.buffers().color, renderer.buffers().display, renderer.pixel_draws()};
}

struct Timing {
  std::vector<double> frame;
  std::map<std::string, std::vector<double>> pass;
};

void time_frames(const RunSetup& setup, const Profile& profile, unsigned threads, int frames,
                 const PluginRegistry& registry, Timing& out) {
  JobSystem jobs(threads);
  Renderer renderer(*setup.scene, setup.description, profile, registry.create_all(), jobs);
  attach_playback(renderer, setup);
  constexpr int kWarmup = 2;
  for (int f = 0; f < kWarmup + frames; ++f) {
    const FrameRecord& rec = renderer.render_frame(f);
    if (f < kWarmup) continue;
    out.frame.push_back(rec.frame_ms);
    for (const PassTiming& p : rec.passes) out.pass[p.name].push_back(p.ms());
  }
}

}  // namespace

int antialiasing_command(const std::vector<std::string>& args, const PluginRegistry& registry) {
  ArgParser p("aa-error", "cpurender aa-error [SCENE] [options]",
              "Edge error of each anti-aliasing mode against a K x K supersampled render of the same frame\n"
              "(linear box filter, then the display transform), and each pass's cost at 1 and 2 threads.\n"
              "The last frame of the scene's frames is compared. Profile settings in pixels (the fog's\n"
              "froxel_size_px) describe a K times finer grid in the reference.");
  add_scene_options(p);
  p.option("modes", "LIST", "comma-separated modes: none, msaa2, msaa4, msaa8", "none,msaa2,msaa4,msaa8")
      .option("factor", "K", "reference samples per pixel along each axis", "4")
      .option("timing-frames", "N", "measured frames per timing run (0: no timing)", "8")
      .option("rounds", "N", "interleaved timing rounds", "3")
      .option("json", "FILE", "also write the results as JSON");
  if (!p.parse(args, 0, 1)) return 0;
  const RunSetup setup = load_run_setup(p, registry);
  std::vector<Mode> modes;
  for (const std::string& m : p.get_list("modes")) modes.push_back(parse_mode(m));
  const int k = p.get_int("factor", 1, 8);
  const int timing_frames = p.get_int("timing-frames", 0, 10000);
  const int rounds = p.get_int("rounds", 1, 100);
  // Edges are found and measured at the pixels the scene renders at.
  if (setup.profile.scaled())
    throw InputError(setup.profile.path, "render_scale: aa-error measures edges at the output size; it must be 1");
  const int w = setup.profile.width, h = setup.profile.height;
  if (size_t(w) * k > size_t(kMaxImageSize) || size_t(h) * k > size_t(kMaxImageSize))
    throw UsageError("aa-error: the reference would be " + std::to_string(w * k) + "x" + std::to_string(h * k) +
                     ", above " + std::to_string(kMaxImageSize) + " pixels a side: lower --resolution or --factor");
  const int last = setup.frames - 1;

  Profile ref_profile = setup.profile;
  ref_profile.width = w * k;
  ref_profile.height = h * k;
  ref_profile.msaa_samples = 1;
  std::printf("aa-error: %s, %dx%d, frame %d, reference %dx%d (%d samples per pixel), %u threads\n",
              setup.description.path.c_str(), w, h, last, w * k, h * k, k * k, setup.threads);
  const Rendered ref = render_last(setup, ref_profile, setup.threads, last, registry);

  // Reference: box filter in linear radiance, then the display transform;
  // edge pixels: their K x K samples see more than one draw (or sky and a draw).
  std::vector<glm::vec3> ref_color(size_t(w) * h, glm::vec3(0.0f));
  std::vector<uint8_t> edge(size_t(w) * h, 0);
  const double inv = 1.0 / double(k * k);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      glm::dvec3 sum(0.0);
      const int32_t first = ref.draws[size_t(y * k) * size_t(w * k) + size_t(x * k)];
      bool mixed = false;
      for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
          const size_t s = size_t(y * k + j) * size_t(w * k) + size_t(x * k + i);
          sum += glm::dvec3(ref.color[s]);
          mixed |= ref.draws[s] != first;
        }
      ref_color[size_t(y) * w + x] = glm::vec3(sum * inv);
      edge[size_t(y) * w + x] = mixed;
    }
  const DisplayTransform display(setup.description.exposure_ev100);
  std::vector<uint8_t> ref_display(size_t(w) * h * 3);
  display.resolve(ref_color.data(), ref_color.size(), ref_display.data());
  const size_t edge_pixels = size_t(std::count(edge.begin(), edge.end(), 1));
  std::printf("edge pixels: %zu of %zu (%.1f%%)\n\n", edge_pixels, edge.size(), 100.0 * double(edge_pixels) / double(edge.size()));

  nlohmann::json out = {{"scene", setup.description.path}, {"resolution", {w, h}}, {"frame", last},
                        {"reference_samples", k * k}, {"edge_pixels", edge_pixels}, {"modes", nlohmann::json::array()}};
  std::printf("%-6s %10s %10s %10s\n", "mode", "edge mean", "edge p95", "all mean");
  for (const Mode& m : modes) {
    Profile profile = setup.profile;
    profile.msaa_samples = m.samples;
    const Rendered r = render_last(setup, profile, setup.threads, last, registry);
    std::vector<double> edge_err;
    double all = 0.0;
    for (size_t i = 0; i < size_t(w) * h; ++i) {
      double e = 0.0;
      for (int c = 0; c < 3; ++c) e += std::abs(int(r.display[3 * i + c]) - int(ref_display[3 * i + c]));
      e /= 3.0;
      all += e;
      if (edge[i]) edge_err.push_back(e);
    }
    double edge_mean = 0.0;
    for (double e : edge_err) edge_mean += e;
    edge_mean = edge_err.empty() ? 0.0 : edge_mean / double(edge_err.size());
    const double edge_p95 = edge_err.empty() ? 0.0 : percentile_nearest_rank(edge_err, 95);
    all /= double(size_t(w) * h);
    std::printf("%-6s %10.2f %10.2f %10.3f\n", m.name.c_str(), edge_mean, edge_p95, all);
    out["modes"].push_back({{"mode", m.name}, {"edge_mean_codes", edge_mean}, {"edge_p95_codes", edge_p95},
                            {"all_mean_codes", all}});
  }

  if (timing_frames > 0) {
    std::printf("\nmedian ms per pass over %d frames x %d rounds (modes interleaved)\n", timing_frames, rounds);
    for (unsigned threads : {1u, 2u}) {
      std::vector<Timing> timing(modes.size());
      for (int round = 0; round < rounds; ++round)
        for (size_t i = 0; i < modes.size(); ++i) {
          Profile profile = setup.profile;
          profile.msaa_samples = modes[i].samples;
          time_frames(setup, profile, threads, timing_frames, registry, timing[i]);
        }
      std::printf("%u thread%s:\n", threads, threads == 1 ? "" : "s");
      for (size_t i = 0; i < modes.size(); ++i) {
        std::printf("  %-6s frame %7.2f  ", modes[i].name.c_str(), median(timing[i].frame));
        nlohmann::json passes = nlohmann::json::object();
        for (const auto& [name, v] : timing[i].pass) {
          passes[name] = median(v);
          if (median(v) >= 0.05) std::printf(" %s %.2f", name.c_str(), median(v));
        }
        std::printf("\n");
        out["modes"][i]["frame_ms_" + std::to_string(threads) + "t"] = median(timing[i].frame);
        out["modes"][i]["pass_ms_" + std::to_string(threads) + "t"] = passes;
      }
    }
  }
  if (p.has("json")) {
    std::ofstream f(p.get("json"));
    f << out.dump(2) << "\n";
    if (!f) throw Error("aa-error: cannot write " + p.get("json"));
  }
  return 0;
}

}  // namespace cr
