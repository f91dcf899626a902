#include "atmosphere/sky_commands.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>

#include "atmosphere/accuracy_score.h"
#include "atmosphere/atmosphere_plugin.h"
#include "atmosphere/lut_debug_output.h"
#include "atmosphere/reference_merge.h"
#include "atmosphere/reference_renderer.h"
#include "atmosphere/sky_composite.h"
#include "atmosphere/sky_environment.h"
#include "atmosphere/sky_lighting.h"
#include "engine/core/error.h"
#include "engine/shading/brdf.h"
#include "engine/shading/environment_brdf.h"
#include "engine/shading/ggx_sampling.h"
#include "engine/shading/sh_lighting.h"
#include "engine/output/exr_io.h"
#include "engine/output/percentile.h"
#include "engine/render/composite_strips.h"
#include "engine/render/plugin.h"

namespace cr {

namespace {

const char* const kCommandLine = "command line";

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

class Options {
 public:
  Options(const std::vector<std::string>& args, const std::vector<std::string>& allowed) {
    for (size_t i = 0; i < args.size(); ++i) {
      const std::string& a = args[i];
      if (a.rfind("--", 0) != 0) throw InputError(kCommandLine, "unexpected argument \"" + a + "\"");
      const std::string key = a.substr(2);
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end())
        throw InputError(kCommandLine, "unknown option --" + key);
      if (i + 1 >= args.size()) throw InputError(kCommandLine, "--" + key + " needs a value");
      values_[key] = args[++i];
    }
  }
  bool has(const std::string& k) const { return values_.count(k) != 0; }
  std::string text(const std::string& k, const std::string& fallback) const {
    auto it = values_.find(k);
    return it == values_.end() ? fallback : it->second;
  }
  double number(const std::string& k, double fallback, double lo, double hi) const {
    auto it = values_.find(k);
    if (it == values_.end()) return fallback;
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (end == it->second.c_str() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi)
      throw InputError(kCommandLine, "--" + k + " must be a number in [" + std::to_string(lo) + ", " +
                                         std::to_string(hi) + "], got \"" + it->second + "\"");
    return v;
  }
  int integer(const std::string& k, int fallback, int lo, int hi) const {
    const double v = number(k, fallback, lo, hi);
    if (v != std::floor(v)) throw InputError(kCommandLine, "--" + k + " must be an integer");
    return int(v);
  }
  // The comma-separated items of --k (empty items kept; none if it is absent).
  std::vector<std::string> items(const std::string& k) const {
    std::vector<std::string> out;
    auto it = values_.find(k);
    if (it == values_.end()) return out;
    std::stringstream ss(it->second);
    for (std::string item; std::getline(ss, item, ',');) out.push_back(item);
    return out;
  }
  std::vector<double> list(const std::string& k, const std::vector<double>& fallback, double lo, double hi) const {
    if (!has(k)) return fallback;
    std::vector<double> out;
    for (const std::string& item : items(k)) {
      char* end = nullptr;
      const double v = std::strtod(item.c_str(), &end);
      if (item.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi)
        throw InputError(kCommandLine, "--" + k + ": \"" + item + "\" is not a number in [" + std::to_string(lo) +
                                           ", " + std::to_string(hi) + "]");
      out.push_back(v);
    }
    if (out.empty()) throw InputError(kCommandLine, "--" + k + " is empty");
    return out;
  }

 private:
  std::map<std::string, std::string> values_;
};

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot be read");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, std::string("invalid JSON: ") + e.what());
  }
}

struct Setup {
  AtmosphereSceneConfig scene;
  AtmosphereSettings settings;
};

// --scene FILE (its "atmosphere" section) or --preset NAME; --profile FILE (its "atmosphere" section).
Setup load_setup(const Options& o) {
  Setup s;
  if (o.has("scene")) {
    const std::string path = o.text("scene", "");
    const nlohmann::json doc = read_json(path);
    if (!doc.is_object() || !doc.contains("atmosphere"))
      throw InputError(path, "atmosphere: the scene has no atmosphere section");
    s.scene = parse_atmosphere_scene(doc["atmosphere"], path);
  } else {
    s.scene = parse_atmosphere_scene(nlohmann::json{{"preset", o.text("preset", "earth-clear")}}, kCommandLine);
  }
  if (o.has("profile")) {
    const std::string path = o.text("profile", "");
    const nlohmann::json doc = read_json(path);
    s.settings = parse_atmosphere_settings(doc.is_object() && doc.contains("atmosphere") ? doc["atmosphere"]
                                                                                         : nlohmann::json(),
                                           path);
  }
  return s;
}

unsigned thread_option(const Options& o) {
  return unsigned(o.integer("threads", int(JobSystem::default_thread_count()), 1, 1024));
}

float luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

glm::vec3 sun_at_zenith_angle(double zenith_deg) {
  const double z = zenith_deg * M_PI / 180.0;
  return glm::vec3(float(std::sin(z)), float(std::cos(z)), 0.0f);
}

// A camera `altitude` metres above the ground looking at the horizon towards +X
// (the sun's azimuth), and the scheduler/frame state for it.
struct SkyCase {
  std::unique_ptr<LutScheduler> luts;
  AtmospherePlan plan;
  SkyFrame frame;
  Camera camera;
  glm::dvec3 offset;
};

void update_case(SkyCase& c, int frame, const Camera& camera, const glm::vec3& sun, const glm::vec3& illuminance,
                 JobSystem& jobs) {
  c.camera = camera;
  c.plan = c.luts->plan(frame_inputs(c.luts->model(), c.offset, frame, camera, sun));
  c.luts->run_all(c.plan, jobs);
  c.frame = make_sky_frame(*c.luts, c.plan, camera, c.offset, illuminance);
}

SkyCase make_case(const Setup& setup, const AtmosphereSettings& settings) {
  SkyCase c;
  c.luts = std::make_unique<LutScheduler>(settings);
  c.luts->set_model(setup.scene.model);
  c.offset = planet_offset(setup.scene);
  return c;
}

Camera horizon_camera(double altitude, int width, int height) {
  return Camera::look_at(glm::dvec3(0.0, altitude, 0.0), glm::dvec3(1000.0, altitude, 0.0), 1.0471976f,
                         float(width) / float(height), 0.1f);
}

// Panorama directions: azimuth 0..360 deg from the sun's azimuth, elevation top_deg .. bottom_deg.
std::vector<glm::vec3> panorama(int width, int height, double top_deg, double bottom_deg) {
  std::vector<glm::vec3> d(size_t(width) * height);
  for (int y = 0; y < height; ++y) {
    const double e = (top_deg - (y + 0.5) / height * (top_deg - bottom_deg)) * M_PI / 180.0;
    for (int x = 0; x < width; ++x) {
      const double a = 2.0 * M_PI * (x + 0.5) / width;
      d[size_t(y) * width + x] = glm::vec3(float(std::cos(e) * std::cos(a)), float(std::sin(e)),
                                           float(std::cos(e) * std::sin(a)));
    }
  }
  return d;
}

struct ErrorStats {
  double mean = 0.0;
  double p95 = 0.0;
  size_t count = 0;
};

ErrorStats relative_error(const std::vector<glm::vec3>& test, const std::vector<glm::vec3>& ref,
                          const std::vector<bool>& mask) {
  std::vector<double> e;
  for (size_t i = 0; i < ref.size(); ++i) {
    if (!mask.empty() && !mask[i]) continue;
    const double yr = luminance(ref[i]);
    const double yt = luminance(test[i]);
    e.push_back(std::abs(yt - yr) / std::max(yr, 1e-9));
  }
  ErrorStats s;
  s.count = e.size();
  if (e.empty()) return s;
  double sum = 0.0;
  for (double v : e) sum += v;
  s.mean = sum / double(e.size());
  s.p95 = percentile_nearest_rank(e, 95.0);
  return s;
}

void write_radiance_exr(const std::string& path, const std::vector<glm::vec3>& px, int w, int h) {
  ExrImage img;
  img.color = ImageRGBf(w, h);
  for (size_t i = 0; i < px.size(); ++i)
    for (int c = 0; c < 3; ++c) img.color.rgb[i * 3 + size_t(c)] = px[i][c];
  write_exr(path, img);
}

void write_reference_exr(const std::string& path, const std::vector<glm::vec3>& px, const std::vector<float>& y,
                         const std::vector<float>& noise, int w, int h) {
  ExrImage img;
  img.color = ImageRGBf(w, h);
  for (size_t i = 0; i < px.size(); ++i)
    for (int c = 0; c < 3; ++c) img.color.rgb[i * 3 + size_t(c)] = px[i][c];
  img.aovs.push_back({"Y", ExrPixelType::Float, y});
  img.aovs.push_back({"noise", ExrPixelType::Float, noise});
  write_exr(path, img);
}

// A reference written by --out: its luminance (full float) and noise channels.
void read_reference_exr(const std::string& path, int w, int h, std::vector<float>& y, std::vector<float>& noise) {
  const ExrImage img = read_exr(path);
  if (img.color.width != w || img.color.height != h)
    throw InputError(path, "size " + std::to_string(img.color.width) + "x" + std::to_string(img.color.height) +
                               " does not match --width/--height " + std::to_string(w) + "x" + std::to_string(h));
  y.clear();
  noise.clear();
  for (const ExrChannel& c : img.aovs) {
    if (c.name == "Y") y = c.values;
    if (c.name == "noise") noise = c.values;
  }
  if (y.empty() || noise.empty()) throw InputError(path, "channels Y and noise: missing (not written by sky-accuracy --out)");
}

// The references of one case from every directory of --reference that has it, merged.
ReferenceLuminance read_references(const std::vector<std::string>& dirs, const std::string& file, int w, int h) {
  std::vector<ReferenceLuminance> refs;
  for (const std::string& dir : dirs) {
    const std::string path = dir + "/" + file;
    if (!std::filesystem::exists(path)) continue;
    ReferenceLuminance r;
    read_reference_exr(path, w, h, r.luminance, r.noise);
    refs.push_back(std::move(r));
  }
  if (refs.empty()) throw InputError(file, "not found in any --reference directory");
  return merge_references(refs, file);
}

const char* const kAccuracyUsage =
    "usage: sky-accuracy [--preset NAME | --scene FILE] [--profile FILE] [--sun-zenith 0,45,80,90,95]\n"
    "                    [--altitude 1,1000,10000] [--width 48] [--height 24] [--spp 4096] [--seed 1]\n"
    "                    [--threads N] [--out DIR] [--reference DIR[,DIR...]]\n"
    "Renders a panorama (azimuth 0-360 deg from the sun, elevation 90 to -10 deg; from above the space\n"
    "altitude 0 to -90 deg) with the LUT method and the path-traced reference and prints, per case:\n"
    "  mean, p95   relative luminance error |Y_lut - Y_ref| / Y_ref over the scored pixels: sky above the\n"
    "              horizon (from space: every direction that meets the atmosphere) whose reference\n"
    "              luminance is at least 1% of their mean; the pixels below that floor (night, earth shadow)\n"
    "              are counted (dark) and their mean absolute error relative to that mean is dark_err;\n"
    "  noise       the reference's Monte-Carlo standard error relative to its luminance (mean over the\n"
    "              scored pixels) and bias = sqrt(rms_error^2 - rms_noise^2), the error the noise does not\n"
    "              explain; \"within ref noise\" when rms_error <= 1.2 rms_noise;\n"
    "  all_mean    the same mean over every pixel (ground below the horizon included);\n"
    "  lut_ms, ref_ms  the time of each (ref_ms 0 with --reference).\n"
    "A missed case whose unexplained error is over 3% and 3x the noise is marked biased (more paths would\n"
    "not change the verdict); otherwise a noisy reference is marked \"ref noise too high\".\n"
    "Targets: mean <= 3%, p95 <= 8%. --out DIR writes both images as EXR (the reference with Y and noise\n"
    "channels); --reference DIR reads such references instead of rendering them (same view options).\n"
    "Several directories (references rendered with different --seed) are merged per case, each image\n"
    "weighted by its path count (1 / its mean squared noise); a case uses every directory that has it.\n"
    "Exit status: 0 all cases within the targets, 1 a case misses them, 2 usage or input error.";

}  // namespace

int sky_accuracy_command(const std::vector<std::string>& args) {
  const Options o(args, {"preset", "scene", "profile", "sun-zenith", "altitude", "width", "height", "spp", "threads",
                         "out", "seed", "reference"});
  const Setup setup = load_setup(o);
  const std::vector<double> zeniths = o.list("sun-zenith", {0, 45, 80, 90, 95}, 0.0, 180.0);
  const std::vector<double> altitudes = o.list("altitude", {1, 1000, 10000}, 0.0, 1e7);
  const int w = o.integer("width", 48, 2, 4096);
  const int h = o.integer("height", 24, 2, 4096);
  ReferenceSettings rs;
  // 4096 paths keep the reference's relative standard error well below the 3% target (~0.5-1%).
  rs.samples_per_pixel = o.integer("spp", 4096, 0, 1 << 20);
  rs.seed = uint64_t(o.integer("seed", 1, 0, 1 << 30));
  const std::string out = o.text("out", "");
  const std::string stored = o.text("reference", "");
  std::vector<std::string> stored_dirs = o.items("reference");
  std::erase(stored_dirs, std::string());
  if (!out.empty()) std::filesystem::create_directories(out);
  JobSystem jobs(thread_option(o));
  AtmosphereSettings full = setup.settings;
  full.full_schedule = true;
  const glm::vec3 e(110000.0f);

  if (stored.empty())
    std::printf("sky-accuracy: preset %s, %dx%d panorama, %d paths/pixel, %u threads\n", setup.scene.preset.c_str(),
                w, h, rs.samples_per_pixel, jobs.thread_count());
  else
    std::printf("sky-accuracy: preset %s, %dx%d panorama, references from %s, %u threads\n",
                setup.scene.preset.c_str(), w, h, stored.c_str(), jobs.thread_count());
  std::printf("%7s %7s | %7s %7s | %7s %7s | %5s %8s | %8s | %8s %8s | %s\n", "sun_zen", "alt_m", "mean", "p95",
              "noise", "bias", "dark", "dark_err", "all_mean", "lut_ms", "ref_ms", "verdict");
  bool all_pass = true;
  for (double alt : altitudes) {
    // From space (the space fallback) the view is the planet and its limb: elevation 0 to -90 deg.
    const bool from_space = alt > full.space_altitude;
    const std::vector<glm::vec3> dirs = from_space ? panorama(w, h, 0.0, -90.0) : panorama(w, h, 90.0, -10.0);
    for (double zen : zeniths) {
      char name[128];
      std::snprintf(name, sizeof name, "sun%g_alt%g", zen, alt);
      const glm::vec3 sun = sun_at_zenith_angle(zen);
      SkyCase c = make_case(setup, full);
      const double t0 = now_ms();
      update_case(c, 0, horizon_camera(alt, 16, 9), sun, e, jobs);
      std::vector<glm::vec3> lut(dirs.size());
      jobs.parallel_for("atmosphere.accuracy", dirs.size(), 64, [&](size_t b, size_t en) {
        for (size_t i = b; i < en; ++i) lut[i] = sky_radiance(c.frame, dirs[i], false);
      });
      const double lut_ms = now_ms() - t0;

      std::vector<float> ref_y(dirs.size()), ref_noise;
      double ref_ms = 0.0;
      if (!stored.empty()) {
        ReferenceLuminance merged = read_references(stored_dirs, std::string(name) + "_reference.exr", w, h);
        ref_y = std::move(merged.luminance);
        ref_noise = std::move(merged.noise);
      } else {
        ReferenceView view;
        view.origin = glm::dvec3(0.0, c.frame.model.bottom_radius + setup.scene.ground_altitude + alt, 0.0);
        view.directions = dirs;
        view.sun_direction = sun;
        view.sun_illuminance = e;
        std::mutex print_mutex;
        int last_percent = -1;
        const double r0 = now_ms();
        const ReferenceImage ref = render_reference(c.frame.model, view, rs, jobs, [&](size_t done, size_t total) {
          const int percent = int(100 * done / total);
          std::lock_guard<std::mutex> lock(print_mutex);
          if (percent / 10 != last_percent / 10) {
            last_percent = percent;
            std::fprintf(stderr, "\r  reference sun %g deg, %g m: %3d%%", zen, alt, percent);
            std::fflush(stderr);
          }
        });
        ref_ms = now_ms() - r0;
        std::fprintf(stderr, "\r%60s\r", "");
        for (size_t i = 0; i < dirs.size(); ++i) ref_y[i] = luminance(ref.radiance[i]);
        ref_noise = ref.noise;
        if (!out.empty()) write_reference_exr(out + "/" + name + "_reference.exr", ref.radiance, ref_y, ref_noise, w, h);
      }

      std::vector<bool> sky(dirs.size());
      // Considered: sky above the horizon; from space, every direction that meets the atmosphere.
      const float mu_top = -float(std::sqrt(std::max(0.0, 1.0 - std::pow(c.frame.model.top_radius / c.frame.camera_radius, 2))));
      for (size_t i = 0; i < dirs.size(); ++i) {
        const float mu = glm::dot(dirs[i], glm::vec3(0, 1, 0));
        sky[i] = from_space ? mu < mu_top : mu > c.frame.mu_horizon;
      }
      std::vector<float> lut_y(dirs.size());
      for (size_t i = 0; i < dirs.size(); ++i) lut_y[i] = luminance(lut[i]);
      const AccuracyScore es = score_accuracy(lut_y, ref_y, ref_noise, sky);
      const AccuracyScore ea = score_accuracy(lut_y, ref_y, ref_noise, {});
      const bool pass = es.scored > 0 && es.mean <= 0.03 && es.p95 <= 0.08;
      all_pass = all_pass && pass;
      std::string verdict = pass ? "pass" : "FAIL";
      if (es.within_noise) verdict += " (error within ref noise)";
      // Noise whose expected error is over a third of the mean target cannot tell a pass from a miss,
      // unless the error the noise does not explain is itself well over the target: then more paths
      // would not change the verdict, the method is biased there.
      const bool biased_beyond_noise = es.bias_rms > 0.03 && es.bias_rms > 3.0 * es.noise_rms;
      if (!pass && biased_beyond_noise) {
        char note[96];
        if (es.noise_rms > 0.0)
          std::snprintf(note, sizeof note, " (biased: %.0fx the ref noise, not noise-limited)", es.bias_rms / es.noise_rms);
        else
          std::snprintf(note, sizeof note, " (biased)");
        verdict += note;
      } else if (es.noise_expected > 0.01) {
        verdict += " (ref noise too high: raise --spp)";
      }
      std::printf("%7.1f %7.0f | %6.2f%% %6.2f%% | %6.2f%% %6.2f%% | %5zu %7.2f%% | %7.2f%% | %8.1f %8.0f | %s\n", zen,
                  alt, 100 * es.mean, 100 * es.p95, 100 * es.noise_mean, 100 * es.bias_rms, es.dark,
                  100 * es.dark_error, 100 * ea.mean, lut_ms, ref_ms, verdict.c_str());
      std::fflush(stdout);
      if (!out.empty()) write_radiance_exr(out + "/" + name + "_lut.exr", lut, w, h);
    }
  }
  std::printf("%s\n", all_pass ? "all cases within the targets" : "some cases exceed the targets");
  return all_pass ? 0 : 1;  // like compare and golden: a missed target is a failed check
}

namespace {

// Bake time of one slice range of one LUT, built from the published LUTs of `base`.
double time_bake(LutKind kind, const LutScheduler& base, const AtmosphereFrameInputs& in, int slice, int slices,
                 JobSystem& jobs) {
  const AtmosphereSettings& s = base.settings();
  const AtmosphereModel& m = base.model();
  const TransmittanceLut& t = *base.multiscattering_source();
  const MultiScatteringLut& ms = *base.multiscattering();
  const AtmosphereLuts luts{m, t, ms};
  auto timed = [&](size_t items, size_t granule, const std::function<void(size_t, size_t)>& bake) {
    const size_t b = slice_begin(items, granule, slice, slices), e = slice_begin(items, granule, slice + 1, slices);
    const double t0 = now_ms();
    jobs.parallel_for("bench", e - b, granule, [&](size_t x, size_t y) { bake(b + x, b + y); });
    return now_ms() - t0;
  };
  switch (kind) {
    case LutKind::Transmittance: {
      TransmittanceLut lut(m, s.transmittance_width, s.transmittance_height, s.transmittance_steps);
      return timed(lut.texel_count(), size_t(s.transmittance_width), [&](size_t b, size_t e) { lut.bake(b, e); });
    }
    case LutKind::MultiScattering: {
      // The scheduler's own explicit orders, chosen once for this atmosphere.
      const std::shared_ptr<MultiScatteringLut> made = new_multiscattering_lut(m, s, ms.explicit_orders());
      MultiScatteringLut& lut = *made;
      const size_t granule = size_t(s.multiscattering_width);
      const size_t b = slice_begin(lut.work_items(), granule, slice, slices);
      const size_t e = slice_begin(lut.work_items(), granule, slice + 1, slices);
      const double t0 = now_ms();
      bake_in_jobs(lut, b, e, granule, t, jobs, "bench");
      return now_ms() - t0;
    }
    case LutKind::SkyView: {
      const glm::dvec3 up = in.camera.position / in.radius();
      SkyViewLut lut(s.skyview_width, s.skyview_height, s.skyview_min_steps, s.skyview_max_steps,
                     float(in.altitude()), float(glm::dot(glm::dvec3(in.camera.sun_direction), up)), m.bottom_radius,
                     m.top_radius);
      return timed(lut.texel_count(), size_t(s.skyview_width), [&](size_t b, size_t e) { lut.bake(b, e, luts); });
    }
    case LutKind::AerialPerspective: {
      AerialPerspectiveLut lut(s.ap_width, s.ap_height, s.ap_depth, s.ap_km_per_slice, s.ap_steps_per_slice,
                               in.camera);
      return timed(lut.column_count(), size_t(s.ap_width), [&](size_t b, size_t e) { lut.bake(b, e, luts); });
    }
  }
  return 0.0;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// A synthetic frame: sky above the horizon, ground geometry below at the distance a flat plane would be
// (no geometry at all for an altitude of 0).
void fill_test_buffers(FrameBuffers& b, const Camera& cam, double altitude) {
  for (int y = 0; y < b.height; ++y)
    for (int x = 0; x < b.width; ++x) {
      const glm::vec3 d = cam.ray_direction(float(x) + 0.5f, float(y) + 0.5f, b.width, b.height);
      const size_t i = b.index(x, y);
      if (altitude > 0.0 && d.y < -1e-4f) {
        b.distance[i] = float(std::min(altitude / -double(d.y), 3e5));
        b.depth[i] = cam.znear / b.distance[i];
        b.color[i] = glm::vec3(0.1f, 0.12f, 0.08f) * 20000.0f;
      } else {
        b.distance[i] = std::numeric_limits<float>::infinity();
        b.depth[i] = 0.0f;
        b.color[i] = glm::vec3(0.0f);
      }
    }
}

// Process CPU time: on a shared machine the wall time of a job also counts other people's work.
double cpu_ms() { return 1000.0 * double(std::clock()) / double(CLOCKS_PER_SEC); }

struct CompositeTime {
  double wall_ms = 0.0;
  double cpu_ms = 0.0;  // all threads together
};

CompositeTime time_composite(const SkyFrame& f, FrameBuffers& b, JobSystem& jobs) {
  const double t0 = now_ms(), c0 = cpu_ms();
  // Split as the engine's composite pass splits it.
  for_each_composite_strip(jobs, "composite", b.width, b.height,
                           [&](int x0, int y0, int x1, int y1) { composite_sky(f, b, x0, y0, x1, y1); });
  return {now_ms() - t0, cpu_ms() - c0};
}

// Median composite time over `repeat` runs on freshly filled buffers.
CompositeTime median_composite(const SkyFrame& f, const Camera& cam, double altitude, int width, int height,
                               int repeat, JobSystem& jobs);

CompositeTime median_composite(const SkyFrame& f, const Camera& cam, double altitude, int width, int height,
                               int repeat, JobSystem& jobs) {
  FrameBuffers b;
  b.resize(width, height);
  std::vector<double> wall, cpu;
  for (int r = 0; r < repeat; ++r) {
    fill_test_buffers(b, cam, altitude);
    const CompositeTime t = time_composite(f, b, jobs);
    wall.push_back(t.wall_ms);
    cpu.push_back(t.cpu_ms);
  }
  return {median(wall), median(cpu)};
}

const char* const kBenchUsage =
    "usage: sky-bench [--preset NAME | --scene FILE] [--profile FILE] [--threads N] [--repeat 7]\n"
    "                 [--width 1280] [--height 720] [--frames 240]";

}  // namespace

int sky_bench_command(const std::vector<std::string>& args) {
  const Options o(args, {"preset", "scene", "profile", "threads", "repeat", "width", "height", "frames"});
  const Setup setup = load_setup(o);
  const unsigned all_threads = thread_option(o);
  const int repeat = o.integer("repeat", 7, 1, 1000);
  const int width = o.integer("width", 1280, 16, 16384);
  const int height = o.integer("height", 720, 16, 16384);
  const int frames = o.integer("frames", 240, 2, 100000);
  const AtmosphereSettings& s = setup.settings;
  AtmosphereSettings full = s;
  full.full_schedule = true;
  const glm::vec3 e(110000.0f);
  const double altitude = 2.0;
  const Camera cam = Camera::look_at(glm::dvec3(0.0, altitude, 0.0), glm::dvec3(1000.0, altitude - 40.0, 300.0),
                                     1.0471976f, float(width) / float(height), 0.1f);
  const glm::vec3 sun = glm::normalize(glm::vec3(0.6f, 0.5f, 0.4f));

  std::vector<unsigned> thread_counts{1};
  if (all_threads > 1) thread_counts.push_back(all_threads);
  std::printf("sky-bench: preset %s, median of %d runs\n", setup.scene.preset.c_str(), repeat);
  const double o0 = now_ms();
  const ExplicitOrderChoice orders = explicit_orders_for(setup.scene.model, s);
  const double orders_ms = now_ms() - o0;
  std::printf("LUT sizes: transmittance %dx%d/%d steps, multi-scattering %dx%d x %d dirs x %d steps + %d explicit "
              "orders (f_ms up to %.3f; chosen in %.2f ms, once per atmosphere), sky-view %dx%d (%d-%d steps), AP %dx%dx%d (%g km/slice)\n",
              s.transmittance_width, s.transmittance_height, s.transmittance_steps, s.multiscattering_width,
              s.multiscattering_height, s.multiscattering_directions, s.multiscattering_steps, orders.orders,
              double(orders.max_fms), orders_ms, s.skyview_width, s.skyview_height,
              s.skyview_min_steps, s.skyview_max_steps, s.ap_width, s.ap_height, s.ap_depth, s.ap_km_per_slice);
  std::map<unsigned, std::array<double, kLutKinds>> full_ms, slice_ms;
  std::map<unsigned, CompositeTime> composite_ms, space_ms;
  // The space fallback: from 400 km, looking at the limb (sky-view LUT seen from space; no geometry).
  const double orbit = 400e3;
  const Camera orbit_cam = Camera::look_at(glm::dvec3(0.0, orbit, 0.0), glm::dvec3(2200e3, 0.0, 0.0), 1.0471976f,
                                           float(width) / float(height), 1.0f);
  double space_lut_ms = 0.0;
  for (unsigned threads : thread_counts) {
    JobSystem jobs(threads);
    SkyCase c = make_case(setup, full);
    update_case(c, 0, cam, sun, e, jobs);
    const AtmosphereFrameInputs in = c.plan.inputs;
    for (int k = 0; k < kLutKinds; ++k) {
      std::vector<double> f, sl;
      const int slices = s.schedule[size_t(k)].slices;
      for (int r = 0; r < repeat; ++r) {
        f.push_back(time_bake(LutKind(k), *c.luts, in, 0, 1, jobs));
        double worst = 0.0;
        for (int q = 0; q < slices; ++q) worst = std::max(worst, time_bake(LutKind(k), *c.luts, in, q, slices, jobs));
        sl.push_back(worst);
      }
      full_ms[threads][size_t(k)] = median(f);
      slice_ms[threads][size_t(k)] = median(sl);
    }
    composite_ms[threads] = median_composite(c.frame, cam, altitude, width, height, repeat, jobs);
    SkyCase space = make_case(setup, full);
    const double s0 = now_ms();
    update_case(space, 0, orbit_cam, sun, e, jobs);
    if (threads == thread_counts.back()) space_lut_ms = now_ms() - s0;
    space_ms[threads] = median_composite(space.frame, orbit_cam, 0.0, width, height, repeat, jobs);
  }
  const unsigned hi = thread_counts.back();
  std::printf("\n%-20s %10s %10s %7s %7s %12s %14s\n", "LUT", "full 1T", "full NT", "period", "slices",
              "worst slice", "amortised/frm");
  double sum1 = 0, sumN = 0, amortised = 0;
  for (int k = 0; k < kLutKinds; ++k) {
    const LutSchedule& sc = s.schedule[size_t(k)];
    const double a = full_ms[hi][size_t(k)] / sc.period;
    sum1 += full_ms[1][size_t(k)];
    sumN += full_ms[hi][size_t(k)];
    amortised += a;
    std::printf("%-20s %8.2fms %8.2fms %7d %7d %10.2fms %12.3fms\n", lut_name(LutKind(k)), full_ms[1][size_t(k)],
                full_ms[hi][size_t(k)], sc.period, sc.slices, slice_ms[hi][size_t(k)], a);
  }
  std::printf("%-20s %8.2fms %8.2fms %7s %7s %12s %12.3fms\n", "all four", sum1, sumN, "", "", "", amortised);
  std::printf("(NT = %u threads; amortised = full NT / period, the cost when the inputs change every frame)\n", hi);
  std::printf("composite %dx%d (sky + aerial perspective): %.2f ms 1T, %.2f ms %uT wall (%.2f / %.2f ms CPU)\n",
              width, height, composite_ms[1].wall_ms, composite_ms[hi].wall_ms, hi, composite_ms[1].cpu_ms,
              composite_ms[hi].cpu_ms);
  std::printf("composite %dx%d from %.0f km (space fallback, sky only): %.2f ms 1T, %.2f ms %uT wall (%.2f / %.2f ms "
              "CPU); its four LUTs %.2f ms %uT\n",
              width, height, orbit / 1000.0, space_ms[1].wall_ms, space_ms[hi].wall_ms, hi, space_ms[1].cpu_ms,
              space_ms[hi].cpu_ms, space_lut_ms, hi);

  // What amortisation costs: the profile's schedules against a full rebuild every frame,
  // along a camera path (walking, turning, climbing) under a moving sun.
  JobSystem jobs(all_threads);
  SkyCase amortised_case = make_case(setup, s);
  SkyCase full_case = make_case(setup, full);
  const int pw = 160, ph = 90;
  FrameBuffers ba, bf;
  std::vector<double> means, p95s, work;
  std::map<std::string, int> causes;
  for (int f = 0; f < frames; ++f) {
    const double t = double(f);
    const glm::dvec3 pos(t * 3.0, altitude + t * 0.5, t * 1.0);
    const double yaw = t * 0.2 * M_PI / 180.0;
    const Camera pc = Camera::look_at(pos, pos + glm::dvec3(std::cos(yaw), -0.05, std::sin(yaw)), 1.0471976f,
                                      float(pw) / float(ph), 0.1f);
    const double elev = (30.0 - t * 0.1) * M_PI / 180.0;  // setting sun, 0.1 deg per frame
    const glm::vec3 ps(float(std::cos(elev) * 0.8), float(std::sin(elev)), float(std::cos(elev) * 0.6));
    update_case(amortised_case, f, pc, glm::normalize(ps), e, jobs);
    update_case(full_case, f, pc, glm::normalize(ps), e, jobs);
    double frame_work = 0.0;
    for (int k = 0; k < kLutKinds; ++k) {
      if (amortised_case.plan.work[size_t(k)].active) {
        frame_work += amortised_case.luts->frame_ms(LutKind(k));
        ++causes[std::string(lut_name(LutKind(k))) + ":" + amortised_case.plan.work[size_t(k)].cause];
      }
    }
    work.push_back(frame_work);
    ba.resize(pw, ph);
    bf.resize(pw, ph);
    fill_test_buffers(ba, pc, pos.y);
    fill_test_buffers(bf, pc, pos.y);
    composite_sky(amortised_case.frame, ba, 0, 0, pw, ph);
    composite_sky(full_case.frame, bf, 0, 0, pw, ph);
    const ErrorStats es = relative_error(ba.color, bf.color, {});
    means.push_back(es.mean);
    p95s.push_back(es.p95);
  }
  double mean_err = 0.0, mean_work = 0.0;
  for (double v : means) mean_err += v;
  for (double v : work) mean_work += v;
  std::printf("\namortisation along a %d-frame path (3 m/frame, 0.2 deg/frame turn, sun setting 0.1 deg/frame),\n"
              "%dx%d, vs a full rebuild every frame: mean rel. error %.3f%%, worst-frame p95 %.3f%%\n",
              frames, pw, ph, 100 * mean_err / frames, 100 * *std::max_element(p95s.begin(), p95s.end()));
  std::printf("measured LUT work per frame (%u threads): mean %.3f ms, worst frame %.3f ms\nupdates:", all_threads,
              mean_work / frames, *std::max_element(work.begin(), work.end()));
  for (const auto& [k, n] : causes) std::printf(" %s x%d", k.c_str(), n);
  std::printf("\n");
  return 0;
}

namespace {

// n directions spread evenly over the sphere (spherical Fibonacci).
std::vector<glm::vec3> sphere_directions(int n) {
  std::vector<glm::vec3> d;
  for (int i = 0; i < n; ++i) {
    const float y = 1.0f - 2.0f * (float(i) + 0.5f) / float(n);
    const float a = float(i) * 2.39996323f;
    const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
    d.emplace_back(r * std::cos(a), y, r * std::sin(a));
  }
  return d;
}

// The un-prefiltered sky through a GGX lobe around unit n seen from unit v,
// by `samples` importance-sampled half vectors with no filtering: per sample
// the radiance of its reflected direction and a weight, summed in double.
// lobe: Karis' prefilter integral with n = v (weight n.l, normalised);
// metal: the white metal's reflected radiance, (1/N) sum L f n.l / pdf.
struct LobeReference {
  glm::vec3 lobe{0.0f};
  glm::vec3 metal{0.0f};
};
LobeReference reference_lobe(const SkyFrame& f, const glm::vec3& n, const glm::vec3& v, float roughness,
                             int samples) {
  const float alpha = std::max(roughness * roughness, kMinRoughness * kMinRoughness);
  glm::vec3 t, b;
  orthonormal_frame(n, t, b);
  thread_local std::vector<float> dx, dy, dz, wl, wm;
  thread_local std::vector<glm::vec3> l;
  for (auto* a : {&dx, &dy, &dz, &wl, &wm}) a->assign(size_t(samples) * 2, 0.0f);
  l.resize(size_t(samples) * 2);
  const float nv = glm::dot(n, v);
  for (int i = 0; i < samples; ++i) {
    const glm::vec3 hl = ggx_half_vector(hammersley(uint32_t(i), uint32_t(samples)), alpha);
    const glm::vec3 h = hl.x * t + hl.y * b + hl.z * n;
    // Lobe (v = n): l = reflect(-n, h).
    const glm::vec3 ll = 2.0f * hl.z * h - n;
    const size_t j = size_t(i) * 2;
    dx[j] = ll.x;
    dy[j] = ll.y;
    dz[j] = ll.z;
    wl[j] = std::max(glm::dot(ll, n), 0.0f);
    // Metal: l = reflect(-v, h), weight Vis 4 n.l v.h / n.h (F = 1).
    const float vh = glm::dot(v, h);
    const glm::vec3 lm = 2.0f * vh * h - v;
    const float nl = glm::dot(lm, n);
    dx[j + 1] = lm.x;
    dy[j + 1] = lm.y;
    dz[j + 1] = lm.z;
    wm[j + 1] = nl > 0.0f && vh > 0.0f ? smith_visibility(nl, nv, alpha) * 4.0f * nl * vh / hl.z : 0.0f;
  }
  sky_radiance_batch(f, l.size(), dx.data(), dy.data(), dz.data(), l.data());
  glm::dvec3 lobe(0.0), metal(0.0);
  double w = 0.0;
  for (size_t j = 0; j < l.size(); ++j) {
    lobe += double(wl[j]) * glm::dvec3(l[j]);
    w += double(wl[j]);
    metal += double(wm[j]) * glm::dvec3(l[j]);
  }
  return {glm::vec3(lobe / std::max(w, 1e-30)), glm::vec3(metal / double(samples))};
}

// What shading reads for the white metal at (n, v): the environment along
// the dominant direction times A + B (shade_surface.cpp's rule).
glm::vec3 shaded_metal(const SpecularEnvironment& env, const glm::vec3& n, const glm::vec3& v, float roughness) {
  const float r = std::max(roughness, kMinRoughness), alpha = r * r;
  const float nv = glm::dot(n, v);
  const glm::vec3 refl = 2.0f * nv * n - v;
  const EnvironmentBrdf e = environment_brdf(r, nv);
  return env.sample(refl + (n - refl) * alpha, r) * (e.a + e.b);
}

float relative(const glm::vec3& a, const glm::vec3& ref) {
  const float y = luminance(ref);
  return y > 0.0f ? std::abs(luminance(a) - y) / y : 0.0f;
}

struct ErrorSum {
  double sum = 0.0, worst = 0.0;
  int n = 0;
  void add(double e) {
    sum += e;
    worst = std::max(worst, e);
    ++n;
  }
  double mean() const { return n ? sum / n : 0.0; }
};

// The bake, split into `slices` calls as the schedule splits it; returns each call's time.
std::vector<double> time_environment(const SkyFrame& f, const AtmosphereSettings& s, int slices, JobSystem& jobs) {
  EnvironmentPrefilter p(s.environment_size, s.environment_levels, s.environment_samples);
  std::vector<double> ms;
  for (int q = 0; q < slices; ++q) {
    const double t0 = now_ms();
    p.run(p.slice_begin(q, slices), p.slice_begin(q + 1, slices), sky_environment_radiance(f), jobs, "bench");
    ms.push_back(now_ms() - t0);
  }
  return ms;
}

const char* const kEnvironmentUsage =
    "usage: sky-environment [--preset NAME | --scene FILE] [--profile FILE] [--threads N] [--repeat 7]\n"
    "                       [--directions 96] [--samples 8192] [--frames 240]";

}  // namespace

int sky_environment_command(const std::vector<std::string>& args) {
  const Options o(args, {"preset", "scene", "profile", "threads", "repeat", "directions", "samples", "frames"});
  const Setup setup = load_setup(o);
  const AtmosphereSettings& s = setup.settings;
  const unsigned all_threads = thread_option(o);
  const int repeat = o.integer("repeat", 7, 1, 1000);
  const int ndirs = o.integer("directions", 96, 4, 100000);
  const int samples = o.integer("samples", 8192, 16, 1 << 20);
  const int frames = o.integer("frames", 240, 2, 100000);
  const glm::vec3 e(110000.0f);
  const double altitude = 2.0;
  const Camera cam = horizon_camera(altitude, 16, 9);
  const std::vector<int> sizes = EnvironmentPrefilter::level_sizes(s.environment_size, s.environment_levels);
  std::printf("sky-environment: preset %s, octahedral %d levels (", setup.scene.preset.c_str(), s.environment_levels);
  for (size_t k = 0; k < sizes.size(); ++k) std::printf("%s%d", k ? ", " : "", sizes[k]);
  std::printf("), %d samples/texel at level 0's size, period %d, %d slices\n", s.environment_samples,
              s.environment_schedule.period, s.environment_schedule.slices);

  JobSystem jobs(all_threads);
  const std::vector<glm::vec3> dirs = sphere_directions(ndirs);
  std::vector<float> roughness;
  for (int i = 0; i <= 10; ++i) roughness.push_back(float(i) / 10.0f);
  for (double zenith : {40.0, 80.0}) {
    SkyCase c = make_case(setup, s);
    update_case(c, 0, cam, sun_at_zenith_angle(zenith), e, jobs);
    const double t0 = now_ms();
    const auto env = bake_sky_environment(c.frame, s, jobs);
    const double bake = now_ms() - t0;
    // The ground below the horizon is the sky-view LUT's: against albedo / pi (transmitted sun + SH sky irradiance).
    const glm::vec3 up = c.frame.up;
    const glm::vec3 nadir = sky_radiance(c.frame, -up, false);
    LightEnvironment light;
    fill_light_environment(c.frame, light);
    const glm::vec3 e_sky = sh_irradiance(light.ambient_sh, up);
    const glm::vec3 e_sun = light.sun_illuminance * std::max(glm::dot(light.sun_direction, up), 0.0f);
    const glm::vec3 lambert = c.frame.model.ground_albedo * (e_sun + e_sky) / kBrdfPi;
    std::printf("\nsun zenith %.0f deg, camera %.0f m (bake %.2f ms, %u threads): nadir ground %.0f cd/m^2 in the LUT, "
                "albedo/pi (sun %.0f + sky %.0f lx) = %.0f (ratio %.3f)\n",
                zenith, altitude, bake, all_threads, double(luminance(nadir)), double(luminance(e_sun)),
                double(luminance(e_sky)), double(luminance(lambert)), double(luminance(nadir) / luminance(lambert)));
    std::printf("%-10s %-6s %22s %30s\n", "roughness", "level", "lobe mean / max %",
                "white metal n.v=0.5 mean / max %");
    for (float r : roughness) {
      ErrorSum lobe, metal;
      std::vector<LobeReference> refs(dirs.size());
      std::vector<glm::vec3> views(dirs.size());
      jobs.parallel_for("reference", dirs.size(), 1, [&](size_t b, size_t en) {
        for (size_t i = b; i < en; ++i) {
          glm::vec3 t, bt;
          orthonormal_frame(dirs[i], t, bt);
          views[i] = 0.5f * dirs[i] + 0.8660254f * t;
          refs[i] = reference_lobe(c.frame, dirs[i], views[i], r, samples);
        }
      });
      for (size_t i = 0; i < dirs.size(); ++i) {
        lobe.add(relative(env->sample(dirs[i], r), refs[i].lobe));
        metal.add(relative(shaded_metal(*env, dirs[i], views[i], r), refs[i].metal));
      }
      std::printf("%-10.2f %-6.2f %10.2f / %-10.2f %14.2f / %-10.2f\n", double(r), double(r) * (s.environment_levels - 1),
                  100 * lobe.mean(), 100 * lobe.worst, 100 * metal.mean(), 100 * metal.worst);
    }
  }

  // Bake cost: whole, per slice, amortised over the period, at 1 and N threads.
  std::vector<unsigned> thread_counts{1};
  if (all_threads > 1) thread_counts.push_back(all_threads);
  std::printf("\n%-10s %10s %12s %16s\n", "threads", "full", "worst slice", "amortised/frame");
  for (unsigned threads : thread_counts) {
    JobSystem tj(threads);
    SkyCase c = make_case(setup, s);
    update_case(c, 0, cam, sun_at_zenith_angle(40.0), e, tj);
    std::vector<double> full, worst;
    for (int r = 0; r < repeat; ++r) {
      full.push_back(time_environment(c.frame, s, 1, tj)[0]);
      const std::vector<double> sl = time_environment(c.frame, s, s.environment_schedule.slices, tj);
      worst.push_back(*std::max_element(sl.begin(), sl.end()));
    }
    std::printf("%-10u %8.2fms %10.2fms %14.3fms\n", threads, median(full), median(worst),
                median(full) / s.environment_schedule.period);
  }

  // What the schedule costs: along sky-bench's path (3 m/frame, climbing 0.5 m/frame, turning, the sun setting
  // 0.1 deg/frame), the published environment against one baked from the same frame's sky every frame.
  AtmosphereSettings full = s;
  full.full_schedule = true;
  SkyCase c = make_case(setup, s);
  SkyEnvironment amortised(s), every(full);
  ErrorSum error;
  double worst_frame = 0.0, work = 0.0, worst_work = 0.0;
  int worst_at = 0;
  std::map<std::string, int> causes;
  for (int f = 0; f < frames; ++f) {
    const double t = double(f);
    const glm::dvec3 pos(t * 3.0, altitude + t * 0.5, t * 1.0);
    const double yaw = t * 0.2 * M_PI / 180.0;
    const Camera pc = Camera::look_at(pos, pos + glm::dvec3(std::cos(yaw), -0.05, std::sin(yaw)), 1.0471976f,
                                      16.0f / 9.0f, 0.1f);
    const double elev = (30.0 - t * 0.1) * M_PI / 180.0;
    const glm::vec3 ps(float(std::cos(elev) * 0.8), float(std::sin(elev)), float(std::cos(elev) * 0.6));
    update_case(c, f, pc, glm::normalize(ps), e, jobs);
    const uint64_t upstream = c.luts->version(LutKind::MultiScattering);
    const EnvironmentWork wa = amortised.plan(c.plan, upstream), wf = every.plan(c.plan, upstream);
    amortised.run(wa, c.plan, upstream, c.frame, jobs);
    every.run(wf, c.plan, upstream, c.frame, jobs);
    if (wa.active) ++causes[wa.cause];
    work += amortised.frame_ms();
    worst_work = std::max(worst_work, amortised.frame_ms());
    ErrorSum frame_error;
    for (const glm::vec3& d : dirs)
      for (int k = 0; k < s.environment_levels; ++k) {
        const float r = amortised.front()->roughness(k);
        frame_error.add(relative(amortised.front()->sample(d, r), every.front()->sample(d, r)));
      }
    if (frame_error.mean() > error.worst) worst_at = f;
    error.add(frame_error.mean());
    worst_frame = std::max(worst_frame, frame_error.worst);
  }
  std::printf("\nschedule along a %d-frame path (3 m/frame, climbing 0.5 m/frame, sun setting 0.1 deg/frame), vs a "
              "rebake every frame:\nmean rel. error %.3f%%, worst-frame mean %.3f%% (frame %d), worst sample %.3f%%; "
              "environment work per frame (%u threads): mean %.3f ms, worst %.3f ms\nupdates:",
              frames, 100 * error.mean(), 100 * error.worst, worst_at, 100 * worst_frame, all_threads, work / frames, worst_work);
  for (const auto& [k, n] : causes) std::printf(" %s x%d", k.c_str(), n);
  std::printf("\n");
  return 0;
}

int sky_luts_command(const std::vector<std::string>& args) {
  const Options o(args, {"preset", "scene", "profile", "out", "altitude", "sun-zenith", "threads"});
  if (!o.has("out")) throw InputError(kCommandLine, "sky-luts needs --out DIR");
  const Setup setup = load_setup(o);
  AtmosphereSettings full = setup.settings;
  full.full_schedule = true;
  JobSystem jobs(thread_option(o));
  SkyCase c = make_case(setup, full);
  const double altitude = o.number("altitude", 2.0, -1e4, 1e7);
  const double zenith = o.number("sun-zenith", 60.0, 0.0, 180.0);
  update_case(c, 0, horizon_camera(altitude, 16, 9), sun_at_zenith_angle(zenith), glm::vec3(110000.0f), jobs);
  for (const std::string& p : write_lut_debug_views(*c.luts, o.text("out", ""))) std::printf("wrote %s\n", p.c_str());
  if (c.luts->multiscattering()->clamped_texels() > 0)
    std::printf("note: %d multi-scattering texels clamped f_ms to %.3f (largest f_ms %.3f)\n",
                c.luts->multiscattering()->clamped_texels(), double(full.multiscattering_max_fms),
                double(c.luts->multiscattering()->max_fms_seen()));
  return 0;
}

void register_sky_commands(PluginRegistry& registry) {
  auto wrap = [](int (*fn)(const std::vector<std::string>&), const char* usage) {
    return [fn, usage](const std::vector<std::string>& args) {
      for (const std::string& a : args)
        if (a == "--help" || a == "-h") {
          std::printf("%s\n", usage);
          return 0;
        }
      try {
        return fn(args);
      } catch (const InputError& e) {
        std::fprintf(stderr, "error: %s\n%s\n", e.what(), usage);
        return 2;
      }
    };
  };
  registry.add_command({"sky-accuracy", "sky: LUT method vs path-traced reference (error and time)",
                        wrap(sky_accuracy_command, kAccuracyUsage)});
  registry.add_command({"sky-bench", "sky: per-LUT bake times, composite time, amortisation error",
                        wrap(sky_bench_command, kBenchUsage)});
  registry.add_command({"sky-environment",
                        "sky: prefiltered specular environment accuracy vs brute force, bake and schedule cost",
                        wrap(sky_environment_command, kEnvironmentUsage)});
  registry.add_command({"sky-luts", "sky: write the four LUTs as EXR + false-colour PNG",
                        wrap(sky_luts_command, "usage: sky-luts --out DIR [--preset NAME | --scene FILE] "
                                               "[--profile FILE] [--altitude 2] [--sun-zenith 60] [--threads N]")});
}

}  // namespace cr
