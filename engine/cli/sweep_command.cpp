// `cpurender sweep`: renders a scene at every point of a settings sweep and
// records each point's cost (per-pass and frame times, median and p95 over
// the measured frames) and its error against a reference render of the same
// frames (relative luminance and FLIP of the last frame), as CSV and JSON.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

#include "engine/cli/arg_parser.h"
#include "engine/cli/cache_key.h"
#include "engine/cli/cli_common.h"
#include "engine/cli/paths.h"
#include "engine/cli/shard.h"
#include "engine/cli/sweep_csv.h"
#include "engine/cli/sweep_points.h"
#include "engine/cli/sweep_truth.h"
#include "engine/core/error.h"
#include "engine/output/atomic_file.h"
#include "engine/output/exr_io.h"
#include "engine/output/file_lock.h"
#include "engine/output/image_compare.h"
#include "engine/output/percentile.h"
#include "engine/render/renderer.h"

namespace cr {

namespace {

const char* const kSweepDescription =
    "Renders SCENE (default: the generated default scene) at every point of the cross product of the\n"
    "--axis options, each a profile key (a dotted path into the profile JSON, e.g.\n"
    "atmosphere.skyview_lut.width) with its values, plus \"threads\" and \"resolution\" (WxH). Each point\n"
    "is the --base profile with its keys set; it renders --warmup + --frames frames of the scene's path\n"
    "from --first-frame (a cold start there) and records the\n"
    "median and p95 time of every pass and of the frame over the measured frames, and the error of the\n"
    "last frame against a reference render of the same frames (mean and p95 relative luminance error of\n"
    "the linear frames, mean LDR-FLIP of the displayed ones). The reference is --reference (a profile), by default the base profile with 8x MSAA and,\n"
    "when it has an atmosphere section, the atmosphere's LUTs rebuilt every frame at 15 wavelengths; it is\n"
    "rendered once and cached in --references (default OUT/references) by what it depends on (the build, the reference profile,\n"
    "the scene file, the resolution and the frame count).\n"
    "--point LABEL=PROFILE adds a listed point rendering a whole profile (a name, a file, or auto[:BASE],\n"
    "planned for the scene); --points FILE reads axes and listed points from a sweep file.\n"
    "--truth also measures, at the measured frame, each module the scene uses against its own ground truth\n"
    "(those the plugins' tools register, e.g. a path-traced or ray-marched reference), recorded per point\n"
    "under \"module_error\"; their references are cached there too. --truth-setting\n"
    "MODULE.KEY=VALUE sets a module's reference size or sample count (docs/sweep.md).\n"
    "Writes OUT/sweep.json and OUT/sweep.csv after every point (atomically), and OUT/profiles/ the\n"
    "profile of each point. --resume keeps the points of an earlier run of the same sweep (same scene,\n"
    "base, reference, frames and resolution) and renders the rest: a killed sweep loses only the point\n"
    "it was rendering.\n"
    "--shard I/N renders only the points k with k mod N = I (a Slurm array task or a GNU parallel job\n"
    "each), writing OUT/shard.json; `cpurender merge` joins the shards' folders into one sweep.";

struct PointResult {
  int frames = 0;  // measured
  std::vector<double> frame_ms;
  std::map<std::string, std::vector<double>> pass_ms;
  ImageRGBf last;          // the last frame's linear colour
  ImageRGBf last_display;  // and its resolved sRGB values (0..1), what FLIP compares
  std::optional<AutoPlan> plan;  // an auto point's
  RunSetup setup;                // what it rendered; its scene posed at the last frame
};

ImageRGBf linear_color(const FrameBuffers& b) {
  ImageRGBf img(b.width, b.height);
  for (size_t i = 0; i < b.color.size(); ++i)
    for (int c = 0; c < 3; ++c) img.rgb[3 * i + size_t(c)] = b.color[i][c];
  return img;
}

ImageRGBf display_color(const FrameBuffers& b) {
  ImageRGBf img(b.width, b.height);
  for (size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = float(b.display[i]) / 255.0f;
  return img;
}

// Frames first .. first + warmup + frames - 1 of the scene's path, the first
// `warmup` unmeasured (a cold start at `first`, as a render from there).
PointResult render_point(const std::string& scene, const std::string& profile_path, const PluginRegistry& registry,
                         int width, int height, unsigned threads, int first, int warmup, int frames,
                         RunRequest request = {}) {
  request.frames = first + warmup + frames;
  const RunSetup setup = load_run(scene, profile_path, registry, width, height, threads, {},
                                  MemoryBudget::default_limit(), request);
  JobSystem jobs(threads);
  Renderer renderer(*setup.scene, setup.description, setup.profile, registry.create_all(), jobs);
  attach_playback(renderer, setup);
  PointResult r;
  r.frames = frames;
  r.plan = setup.plan;
  r.setup = setup;
  for (int f = first; f < first + warmup + frames; ++f) {
    const FrameRecord& rec = renderer.render_frame(f);
    if (f < first + warmup) continue;
    r.frame_ms.push_back(rec.frame_ms);
    for (const PassTiming& p : rec.passes) r.pass_ms[p.name].push_back(p.ms());
  }
  r.last = linear_color(renderer.buffers());
  r.last_display = display_color(renderer.buffers());
  return r;
}

nlohmann::json default_reference(nlohmann::json base) {
  base["antialiasing"] = "msaa8";
  if (base.contains("atmosphere") && base["atmosphere"].is_object()) {
    base["atmosphere"]["spectral_samples"] = 15;
    base["atmosphere"]["schedule"]["full"] = true;
  }
  return base;
}

std::string format_eta(double seconds) {
  const int s = int(seconds + 0.5);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%d:%02d", s / 60, s % 60);
  return buf;
}

}  // namespace

int sweep_command(const std::vector<std::string>& args, const PluginRegistry& registry,
                  const ModuleTruthRegistry& truth_registry) {
  ArgParser p("sweep", "cpurender sweep [SCENE] (--axis KEY=V1,V2,... | --point LABEL=PROFILE | --points FILE)... [options]", kSweepDescription);
  p.option("axis", "KEY=V1,V2,...", "an axis of the sweep (repeat for more)")
      .option("point", "LABEL=PROFILE", "also a listed point: a profile (name, file or auto[:BASE]) as it is (repeat for more)")
      .option("points", "FILE", "a sweep file: {\"axes\": {KEY: [values]}, \"points\": [{label, profile, settings}]}")
      .option("error-budget", "FRACTION", "the error budget of auto points (0.02 = 2%)", "0.02")
      .option("plan-table", "FILE", "the planner's table for auto points (default: profiles/planner/auto_table.json)")
      .option("base", "NAME|FILE", "the profile every point starts from", "desktop")
      .option("reference", "NAME|FILE", "the reference profile (default: the base at reference quality)")
      .option("resolution", "WxH", "resolution of every point (a \"resolution\" axis overrides it)", "640x360")
      .option("frames", "N", "measured frames per point", "8")
      .option("warmup", "N", "unmeasured frames first", "2")
      .option("first-frame", "N", "first frame of the scene's path to render (a cold start there)", "0")
      .option("threads", "N", "worker threads (a \"threads\" axis overrides it; default: all cores)")
      .option("truth", "all|none|MODULE,...", "measure these modules against their own ground truths", "all")
      .option("truth-setting", "MODULE.KEY=VALUE", "a ground truth's reference setting (repeat for more)")
      .option("out", "DIR", "output directory", "out/sweep")
      .option("references", "DIR", "cached references, shareable by the shards of a sweep (default: OUT/references)")
      .flag("resume", "keep the finished points of an earlier run of the same sweep");
  add_shard_option(p);
  if (!p.parse(args, 0, 1)) return 0;
  const ShardOption shard = shard_option(p, "sweep");
  const std::string scene = p.positional().empty() ? default_scene_path() : p.positional()[0];
  std::vector<SweepAxis> axes;
  std::vector<SweepPoint> listed;
  if (p.has("points")) {
    const std::string file = p.get("points");
    const nlohmann::json doc = nlohmann::json::parse(read_file_bytes(file), nullptr, false);
    if (doc.is_discarded()) throw InputError(file, "not valid JSON");
    SweepFile f = parse_sweep_file(doc, file);
    axes = std::move(f.axes);
    listed = std::move(f.points);
  }
  for (const std::string& a : p.get_all("axis")) axes.push_back(parse_sweep_axis(a));
  for (const std::string& a : p.get_all("point")) listed.push_back(parse_listed_point(a));
  std::vector<SweepPoint> points = sweep_points(axes);
  points.insert(points.end(), listed.begin(), listed.end());
  if (points.empty()) throw UsageError("sweep: give at least one --axis KEY=V1,V2,..., --point or --points");
  std::set<std::string> ids;
  for (const SweepPoint& q : points)
    if (!ids.insert(q.id()).second) throw UsageError("sweep: two points named '" + q.id() + "'");
  const SweepTruths truths = select_truths(truth_registry, p.get_list("truth"), p.get_all("truth-setting"));
  const RunRequest plan_request = plan_options(p);
  const int frames = p.get_int("frames", 1, 100000), warmup = p.get_int("warmup", 0, 1000);
  const int first = p.get_int("first-frame", 0, 1 << 20);
  const int last_frame = first + warmup + frames - 1;  // the one whose error is measured
  const unsigned threads = threads_option(p);
  const auto [width, height] = parse_resolution(p.get("resolution"), "sweep");
  const std::string out = p.get("out");
  const std::string base_path = resolve_profile_path(p.get("base"));
  const nlohmann::json base = nlohmann::json::parse(read_file_bytes(base_path), nullptr, false);
  if (base.is_discarded() || !base.is_object()) throw InputError(base_path, "not a JSON object");
  const nlohmann::json reference =
      p.has("reference") ? nlohmann::json::parse(read_file_bytes(resolve_profile_path(p.get("reference"))), nullptr, false)
                         : default_reference(base);
  if (reference.is_discarded() || !reference.is_object()) throw InputError(p.get("reference"), "not a JSON object");
  std::filesystem::create_directories(out + "/profiles");
  const std::string references = p.has("references") ? p.get("references") : out + "/references";
  std::filesystem::create_directories(references);

  // What the sweep is: --resume refuses a file of another sweep.
  nlohmann::json doc = {{"scene", scene},          {"base", base},          {"reference", reference},
                        {"frames", frames},        {"warmup", warmup},      {"first_frame", first},
                        {"resolution", {width, height}},
                        {"truth", truths.definition()}, {"axes", nlohmann::json::array()},
                        {"points", nlohmann::json::array()}};
  for (const SweepAxis& a : axes) doc["axes"].push_back({{"key", a.key}, {"values", a.values}});
  const std::string json_path = out + "/sweep.json";
  std::set<std::string> done;
  // A shard's manifest: the sweep's definition (the document without its
  // points, and the scene's bytes) and its points, so `merge` can tell
  // whether shards belong together.
  nlohmann::json definition = doc;
  definition.erase("points");
  definition["scene_bytes"] = cache_name(read_file_bytes(scene));
  ShardManifest manifest = new_shard_manifest("sweep", shard.shard, definition);
  if (shard.given) {
    for (size_t i = 0; i < points.size(); ++i) {
      manifest.items.push_back(points[i].id());
      if (shard.shard.owns(i)) manifest.owned.push_back(points[i].id());
    }
  }
  if (p.has("resume") && std::filesystem::exists(out + "/" + kShardManifestName)) {
    const ShardManifest old = read_shard_manifest(out);
    if (!shard.given || old.shard.index != shard.shard.index || old.shard.count != shard.shard.count)
      throw InputError(out + "/" + kShardManifestName, "--resume: this folder holds shard " + old.shard.label() +
                                                           ", not " + (shard.given ? shard.shard.label() : "the whole sweep"));
  }
  if (p.has("resume") && std::filesystem::exists(json_path)) {
    const nlohmann::json old = nlohmann::json::parse(read_file_bytes(json_path), nullptr, false);
    if (old.is_discarded() || !old.is_object()) throw InputError(json_path, "not a sweep file (JSON object)");
    // A sweep written before ground truths were measured measured none; one
    // written before --first-frame started at frame 0.
    const std::map<std::string, nlohmann::json> defaults = {{"truth", SweepTruths{}.definition()}, {"first_frame", 0}};
    for (const char* k : {"scene", "base", "reference", "frames", "warmup", "first_frame", "resolution", "truth"})
      if (old.value(k, defaults.contains(k) ? defaults.at(k) : nlohmann::json()) != doc[k])
        throw InputError(json_path, std::string("--resume: a different sweep (its \"") + k +
                                        "\" differs); use another --out or drop --resume");
    for (const nlohmann::json& row : old.value("points", nlohmann::json::array()))
      if (row.contains("point")) {
        done.insert(row["point"].get<std::string>());
        doc["points"].push_back(row);
      }
  }

  // The reference render, cached by everything it depends on: the build, the
  // reference profile, the scene file, the resolution and the frames.
  const std::string ref_key = build_hash() + "|" + reference.dump() +
                              "|" + scene + "|" + read_file_bytes(scene) + "|" +
                              std::to_string(width) + "x" + std::to_string(height) + "|" +
                              std::to_string(warmup + frames) + (first > 0 ? "|from " + std::to_string(first) : "");
  const std::string ref_name = cache_name(ref_key);
  const std::string ref_exr = references + "/" + ref_name + ".exr";
  const std::string ref_display_exr = references + "/" + ref_name + ".display.exr";
  // Shards sharing --references render it once: the others wait here, then read it.
  std::optional<FileLock> ref_lock(std::in_place, references + "/" + ref_name + ".lock");
  // Points still to render (a shard's; none when resuming a finished sweep).
  size_t todo = 0;
  for (size_t i = 0; i < points.size(); ++i) todo += shard.shard.owns(i) && !done.count(points[i].id());
  ImageRGBf ref_image, ref_display;
  if (todo == 0) {
    // nothing to compare: no reference is needed
  } else if (std::filesystem::exists(ref_exr) && std::filesystem::exists(ref_display_exr)) {
    ref_image = read_exr(ref_exr).color;
    ref_display = read_exr(ref_display_exr).color;
  } else {
    const std::string ref_profile = references + "/" + ref_name + ".json";
    write_file_atomic(ref_profile, reference.dump(2) + "\n");
    std::fprintf(stderr, "sweep: rendering the reference (%s)\n", ref_profile.c_str());
    const PointResult r = render_point(scene, ref_profile, registry, width, height, threads, first, 0, warmup + frames);
    ref_image = r.last;
    ref_display = r.last_display;
    // Float channels: a frame's radiance (the sun's disk) overflows half floats.
    for (const auto& [path, image] : {std::pair{ref_display_exr, &ref_display}, std::pair{ref_exr, &ref_image}}) {
      std::vector<ExrChannel> channels;  // the linear one last: its presence means both are complete
      for (int c = 0; c < 3; ++c) {
        ExrChannel& ch = channels.emplace_back(ExrChannel{std::string(1, "RGB"[c]), ExrPixelType::Float, {}});
        ch.values.resize(size_t(image->width) * size_t(image->height));
        for (size_t i = 0; i < ch.values.size(); ++i) ch.values[i] = image->rgb[3 * i + size_t(c)];
      }
      write_exr_channels(path, image->width, image->height, channels);
    }
  }

  auto write_manifest = [&] {
    if (!shard.given) return;
    manifest.done.clear();
    for (const std::string& id : manifest.owned)
      if (done.count(id)) manifest.done.push_back(id);
    manifest.complete = manifest.done.size() == manifest.owned.size();
    write_shard_manifest(out, manifest);
  };
  write_manifest();
  ref_lock.reset();
  const auto start = std::chrono::steady_clock::now();
  int rendered = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const SweepPoint& point = points[i];
    if (done.count(point.id()) || !shard.shard.owns(i)) continue;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "\rsweep: point %zu/%zu  %s  elapsed %s  ETA %s        ", i + 1, points.size(),
                 point.id().c_str(), format_eta(elapsed).c_str(),
                 rendered ? format_eta(elapsed / rendered * double(todo - size_t(rendered))).c_str() : "-");
    std::fflush(stderr);
    const bool planned = is_auto_profile(point.profile);
    if (planned && !point.settings.empty())
      throw UsageError("sweep: the point '" + point.id() + "' sets keys of an auto profile; plan a base instead");
    nlohmann::json profile = base;
    if (!point.profile.empty() && !planned) {
      const std::string path = resolve_profile_path(point.profile);
      profile = nlohmann::json::parse(read_file_bytes(path), nullptr, false);
      if (profile.is_discarded() || !profile.is_object()) throw InputError(path, "not a JSON object");
    }
    profile = apply_sweep_point(profile, point);
    int w = width, h = height;
    for (const auto& [key, value] : point.settings)
      if (key == "resolution") {
        w = value[0].get<int>();
        h = value[1].get<int>();
      }
    const std::string profile_path = out + "/profiles/point_" + std::to_string(i) + ".json";
    if (!planned) write_file_atomic(profile_path, profile.dump(2) + "\n");
    const unsigned t = sweep_point_threads(point, threads);
    PointResult r = render_point(scene, planned ? point.profile : profile_path, registry, w, h, t, first, warmup,
                                 frames, plan_request);
    if (planned) write_file_atomic(profile_path, r.plan->profile.dump(2) + "\n");  // what the plan rendered
    nlohmann::json row = {{"point", point.id()}, {"index", i}, {"settings", nlohmann::json::object()},
                          {"threads", t}, {"profile", profile_path}};
    if (!point.label.empty()) row["label"] = point.label;
    if (r.plan) row["plan"] = r.plan->to_json();
    for (const auto& [key, value] : point.settings) row["settings"][key] = value;
    row["frame_ms_p50"] = median(r.frame_ms);
    row["frame_ms_p95"] = percentile_nearest_rank(r.frame_ms, 95);
    row["frame_ms_p99"] = percentile_nearest_rank(r.frame_ms, 99);
    row["passes"] = nlohmann::json::object();
    // mean: amortised over every measured frame, a pass that did not run counting 0 (LUT rebuilds).
    for (const auto& [name, v] : r.pass_ms) {
      double sum = 0.0;
      for (double x : v) sum += x;
      row["passes"][name] = {{"p50", median(v)}, {"p95", percentile_nearest_rank(v, 95)},
                             {"p99", percentile_nearest_rank(v, 99)}, {"mean", sum / r.frames}};
    }
    if (r.last.width == ref_image.width && r.last.height == ref_image.height) {
      // Relative luminance on the linear frames; FLIP on the displayed ones (at the scene's exposure).
      const CompareResult c = compare_images(ref_image, r.last, ImageEncoding::Linear, CompareThresholds{});
      const CompareResult d = compare_images(ref_display, r.last_display, ImageEncoding::Display, CompareThresholds{});
      row["error"] = {{"rel_luminance_mean", c.metrics.rel_luminance_mean},
                      {"rel_luminance_p95", c.metrics.rel_luminance_p95},
                      {"flip_mean", d.metrics.flip_mean}};
    } else {  // a resolution axis: the reference is at --resolution; no like-for-like error
      row["error"] = {{"rel_luminance_mean", nullptr}, {"rel_luminance_p95", nullptr}, {"flip_mean", nullptr}};
    }
    if (!truths.modules.empty()) {
      const ModuleTruthRequest request{*r.setup.scene, r.setup.description, r.setup.profile,
                                       planned ? r.plan->profile : profile, w, h, last_frame, t,
                                       nlohmann::json::object(), references, build_hash()};
      const FileLock truth_lock(references + "/truths.lock");  // each truth reference rendered once
      row["module_error"] = measure_truths(truths, request);
    }
    doc["points"].push_back(row);
    done.insert(point.id());
    ++rendered;
    write_file_atomic(json_path, doc.dump(2) + "\n");
    write_file_atomic(out + "/sweep.csv", sweep_csv(doc));
    write_manifest();
  }
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::fprintf(stderr, "\rsweep: %d point%s rendered, %zu kept, %s%40s\n", rendered, rendered == 1 ? "" : "s",
               done.size() - size_t(rendered), format_eta(total).c_str(), "");
  write_file_atomic(json_path, doc.dump(2) + "\n");
  write_file_atomic(out + "/sweep.csv", sweep_csv(doc));
  std::printf("wrote %s and %s/sweep.csv (%zu points)\n", json_path.c_str(), out.c_str(), doc["points"].size());
  return 0;
}

}  // namespace cr
