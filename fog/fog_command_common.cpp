#include "fog/fog_command_common.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <unistd.h>

#include "engine/core/error.h"
#include "engine/output/percentile.h"
#include "engine/scene/gltf_loader.h"

namespace cr {

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::string resolve_profile(const std::string& name_or_path) {
  if (std::filesystem::exists(name_or_path) || name_or_path.find('/') != std::string::npos) return name_or_path;
  char buf[4096];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof(buf) - 1);
  const std::string exe_dir = n > 0 ? std::filesystem::path(std::string(buf, size_t(n))).parent_path().string() : ".";
  return exe_dir + "/profiles/" + name_or_path + ".json";
}

}  // namespace

std::string FogCommandArgs::get(const std::string& key, const std::string& fallback) const {
  auto it = options.find(key);
  return it == options.end() ? fallback : it->second;
}

int FogCommandArgs::get_int(const std::string& key, int fallback, int min, int max) const {
  return int(get_double(key, fallback, min, max));
}

double FogCommandArgs::get_double(const std::string& key, double fallback, double min, double max) const {
  auto it = options.find(key);
  if (it == options.end()) return fallback;
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (end == it->second.c_str() || *end != '\0' || !(v >= min && v <= max))
    throw Error("--" + key + ": expected a number in [" + std::to_string(min) + ", " + std::to_string(max) +
                "], found '" + it->second + "'");
  return v;
}

FogCommandArgs parse_fog_command_args(const std::vector<std::string>& args, const std::vector<std::string>& allowed) {
  FogCommandArgs out;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a.rfind("--", 0) != 0) {
      if (!out.scene.empty()) throw Error("unexpected argument '" + a + "' (one scene file)");
      out.scene = a;
      continue;
    }
    const std::string key = a.substr(2);
    bool known = false;
    for (const std::string& k : allowed) known = known || k == key;
    if (!known) throw Error("unknown option '" + a + "'");
    if (i + 1 >= args.size()) throw Error("option '" + a + "' needs a value");
    out.options[key] = args[++i];
  }
  if (out.scene.empty()) throw Error("missing scene file (a scene with a \"fog\" section)");
  return out;
}

FogRun load_fog_run(const FogCommandArgs& args, const PluginRegistry& registry) {
  FogRun run;
  const std::vector<std::string> sections = registry.names();
  run.profile = load_profile(resolve_profile(args.get("profile", "desktop")), sections);
  if (args.options.count("resolution")) {
    const std::string r = args.get("resolution", "");
    const size_t x = r.find('x');
    if (x == std::string::npos) throw Error("--resolution: expected WxH, found '" + r + "'");
    run.profile.width = std::stoi(r.substr(0, x));
    run.profile.height = std::stoi(r.substr(x + 1));
    if (run.profile.width < 8 || run.profile.height < 8 || run.profile.width > 16384 || run.profile.height > 16384)
      throw Error("--resolution: each side must be in [8, 16384]");
  }
  run.description = load_scene_description(args.scene, sections);
  if (!run.description.plugins.contains("fog"))
    throw InputError(args.scene, "has no \"fog\" section: nothing to measure");
  run.fog_scene = parse_fog_scene(run.description.plugins.at("fog"), run.description.path);
  if (run.profile.plugins.contains("fog"))
    run.fog_profile = parse_fog_profile(run.profile.plugins.at("fog"), run.profile.path);
  run.fog_profile = resolve_fog_settings(run.fog_profile, run.fog_scene);
  run.scene = std::make_unique<Scene>(load_gltf(run.description.gltf_path));
  return run;
}

std::vector<std::unique_ptr<Plugin>> plugins_without_fog(const PluginRegistry& registry) {
  std::vector<std::unique_ptr<Plugin>> out;
  for (auto& p : registry.create_all())
    if (p->name() != "fog") out.push_back(std::move(p));
  return out;
}

std::vector<glm::vec3> froxel_frame(FroxelFog& fog, const FrameView& view, const Renderer& base, JobSystem& jobs,
                                    FroxelTimes* times) {
  FroxelTimes t;
  auto t0 = std::chrono::steady_clock::now();
  fog.begin_frame(view, jobs, &base.buffers().distance);
  fog.density(jobs);
  t.density = ms_since(t0);
  t0 = std::chrono::steady_clock::now();
  fog.lighting(base.light_environment(), base.shadow_map(), jobs);
  t.lighting = ms_since(t0);
  t0 = std::chrono::steady_clock::now();
  fog.reproject(jobs);
  t.reproject = ms_since(t0);
  t0 = std::chrono::steady_clock::now();
  fog.filter(jobs);
  t.filter = ms_since(t0);
  t0 = std::chrono::steady_clock::now();
  fog.integrate(base.light_environment(), jobs);
  t.integrate = ms_since(t0);
  FrameBuffers b = base.buffers();
  t0 = std::chrono::steady_clock::now();
  const int tile = 64;
  const int tiles_x = (b.width + tile - 1) / tile, tiles_y = (b.height + tile - 1) / tile;
  jobs.parallel_for("fog.composite", size_t(tiles_x) * tiles_y, 1, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      const int x0 = int(i % tiles_x) * tile, y0 = int(i / tiles_x) * tile;
      fog.composite(b, x0, y0, std::min(b.width, x0 + tile), std::min(b.height, y0 + tile));
    }
  });
  t.composite = ms_since(t0);
  if (times) *times = t;
  return b.color;
}

ImageError relative_luminance_error(const std::vector<glm::vec3>& reference, const std::vector<glm::vec3>& test) {
  auto lum = [](const glm::vec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; };
  std::vector<double> e(reference.size());
  double sum = 0.0;
  for (size_t i = 0; i < reference.size(); ++i) {
    const double r = lum(reference[i]);
    e[i] = std::abs(lum(test[i]) - r) / std::max(r, 1e-6);
    sum += e[i];
  }
  ImageError out;
  out.mean = reference.empty() ? 0.0 : sum / double(reference.size());
  out.p95 = percentile_nearest_rank(std::move(e), 95.0);
  return out;
}

}  // namespace cr
