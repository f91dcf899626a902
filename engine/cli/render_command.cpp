// `cpurender render`: renders frames of a scene and writes images and reports.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <set>

#include "engine/cli/arg_parser.h"
#include "engine/cli/cache_key.h"
#include "engine/cli/cli_common.h"
#include "engine/cli/paths.h"
#include "engine/cli/shard.h"
#include "engine/core/error.h"
#include "engine/output/atomic_file.h"
#include "engine/output/chrome_trace.h"
#include "engine/output/run_status.h"
#include "engine/output/timing_report.h"
#include "engine/render/renderer.h"

namespace cr {

namespace {

// A warm-up's target: what a cold start may still change of a frame's values
// (one 8-bit code of a fully history-weighted value).
constexpr double kWarmupTolerance = 1.0 / 256.0;

std::string frame_stem(const std::string& out, int frame) {
  char name[64];
  std::snprintf(name, sizeof name, "/frame_%04d", frame);
  return out + name;
}

// The command line without what does not change the frames (where they go,
// threads, progress, resuming, which shard): equal for every shard of one
// render and for a rerun of it.
nlohmann::json render_definition(const std::vector<std::string>& args, const RunSetup& setup, int first) {
  static const std::set<std::string> with_value = {"--out", "--threads", "--shard"};
  static const std::set<std::string> flags = {"--quiet", "--no-trace", "--resume"};
  nlohmann::json kept = nlohmann::json::array();
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string name = args[i].substr(0, args[i].find('='));
    if (flags.count(args[i])) continue;
    if (with_value.count(name)) {
      if (name == args[i]) ++i;  // "--out DIR"
      continue;
    }
    kept.push_back(args[i]);
  }
  nlohmann::json d = {{"args", kept}, {"first_frame", first}, {"frames", setup.frames},
                      {"scene_bytes", cache_name(read_file_bytes(setup.description.path))}};
  if (std::filesystem::is_regular_file(setup.profile.path))
    d["profile_bytes"] = cache_name(read_file_bytes(setup.profile.path));
  return d;
}

}  // namespace

int render_command(const std::vector<std::string>& args, const PluginRegistry& registry) {
  ArgParser p("render", "cpurender render [SCENE] [options]",
              "Renders frames of a scene (a scene .json or a bare .gltf/.glb; default: the generated\n"
              "default scene) and writes frame_NNNN.png / .exr, report.json and trace.json.\n"
              "--shard I/N renders the I-th of N contiguous blocks of the frames, after rendering\n"
              "--warmup-frames frames before its block unwritten (auto: as many as the scene's plugins\n"
              "need for their temporal state to forget the cold start, Plugin::warmup_frames; all: from\n"
              "the first frame, bit-identical to an unsharded render), and writes OUT/shard.json;\n"
              "`cpurender merge` joins the blocks. --resume keeps the frames an earlier run of the\n"
              "same render wrote and renders the rest (warming up again before the first missing one).");
  add_scene_options(p);
  p.option("out", "DIR", "output directory", "out")
      .option("format", "LIST", "comma-separated frame formats: png, exr, none", "png")
      .option("first-frame", "N", "first frame index of the camera path", "0")
      .option("warmup-frames", "N|auto|all", "frames rendered unwritten before a shard's block or a resumed frame", "auto")
      .flag("resume", "keep the frames of an earlier, interrupted run of the same render in OUT")
      .flag("no-trace", "do not write the Chrome trace (trace.json)")
      .flag("quiet", "no progress output");
  add_shard_option(p);
  if (!p.parse(args, 0, 1)) return 0;

  RunSetup setup = load_run_setup(p, registry);
  const std::string out = p.get("out");
  bool png = false, exr = false;
  for (const std::string& f : p.get_list("format")) {
    if (f == "png") png = true;
    else if (f == "exr") exr = true;
    else if (f != "none") throw UsageError("render: unknown --format '" + f + "' (png, exr, none)");
  }
  const int first = p.get_int("first-frame", 0, 1 << 20);
  const std::string warmup = p.get("warmup-frames");
  const int warmup_n = warmup == "auto" || warmup == "all" ? 0 : p.get_int("warmup-frames", 0, 1 << 20);
  const bool quiet = p.has("quiet");
  const ShardOption shard = shard_option(p, "render");
  const auto [begin, end] = shard.shard.frame_block(first, setup.frames);
  if (setup.plan && !quiet) std::cout << setup.plan->summary();
  std::filesystem::create_directories(out);

  const nlohmann::json definition = render_definition(args, setup, first);
  ShardManifest manifest = new_shard_manifest("render", shard.shard, definition);
  for (int f = first; f < first + setup.frames; ++f) {
    manifest.items.push_back(std::to_string(f));
    if (f >= begin && f < end) manifest.owned.push_back(std::to_string(f));
  }

  // --resume: the leading frames of the block an earlier run of the same
  // render wrote (on disk and in its report, which lists only such frames).
  std::vector<nlohmann::json> resumed;
  const std::string report_path = out + "/report.json";
  if (p.has("resume") && std::filesystem::exists(report_path)) {
    const nlohmann::json old = nlohmann::json::parse(read_file_bytes(report_path), nullptr, false);
    const nlohmann::json none;
    const nlohmann::json& r = old.is_object() ? old.value("extra", none).value("render", none) : none;
    if (!r.is_object() || r.value("definition", none) != definition || r.value("build", "") != build_hash() ||
        r.value("shard", "") != shard.shard.label())
      throw InputError(report_path, "--resume: not an earlier run of this render (another command line, scene, "
                                    "profile, shard or build); use another --out or drop --resume");
    for (const nlohmann::json& frame : old.value("frames", nlohmann::json::array())) {
      const int f = frame.value("frame", -1);
      const std::string stem = frame_stem(out, f);
      if (f != begin + int(resumed.size()) || f >= end || (png && !std::filesystem::exists(stem + ".png")) ||
          (exr && !std::filesystem::exists(stem + ".exr")))
        break;
      resumed.push_back(frame);
    }
  }
  const int resume_at = begin + int(resumed.size());
  for (int f = begin; f < resume_at; ++f) manifest.done.push_back(std::to_string(f));
  if (shard.given) write_shard_manifest(out, manifest);

  JobSystem jobs(setup.threads);
  RunReport report = make_run_report(setup, jobs);
  report.resumed_frames = resumed;
  report.extra["render"] = {{"definition", definition}, {"build", build_hash()}, {"shard", shard.shard.label()},
                            {"block", {begin, end}}};
  int warm = 0;
  // report.json says "running" until the trace, the last file, is written (run_status.h).
  report_run(report_path, report, [&] {
    Renderer renderer(*setup.scene, setup.description, setup.profile, registry.create_all(), jobs);
    renderer.keep_view_distances(exr);  // an EXR frame's depth channel
    attach_playback(renderer, setup);
    // Frames before resume_at are someone else's or already written: warm up
    // on those before it (none when it is the path's first frame).
    const int want = warmup == "all" ? resume_at - first
                     : warmup == "auto" ? renderer.warmup_frames(kWarmupTolerance) : warmup_n;
    warm = resume_at == end ? 0 : std::min(want, resume_at - first);
    report.extra["render"]["warmup_frames"] = warm;
    if (!quiet && warm > 0)
      std::fprintf(stderr, "render: warming up on frames %d..%d\n", resume_at - warm, resume_at - 1);
    auto last_write = std::chrono::steady_clock::now();
    for (int f = resume_at - warm; f < end; ++f) {
      const FrameRecord& rec = renderer.render_frame(f);
      if (f < resume_at) continue;
      const std::string stem = frame_stem(out, f);
      if (png) write_frame_png(stem + ".png", renderer.buffers());
      if (exr) write_frame_exr(stem + ".exr", renderer.buffers());
      // After its files: a report lists exactly the frames on disk.
      report.frames.push_back(to_report_frame(rec));
      manifest.done.push_back(std::to_string(f));
      // A killed run's report lists its frames to within a second (what --resume keeps).
      if (std::chrono::steady_clock::now() - last_write > std::chrono::seconds(1)) {
        write_report_json(report_path, report);
        if (shard.given) write_shard_manifest(out, manifest);
        last_write = std::chrono::steady_clock::now();
      }
      if (!quiet && end - resume_at > 1)
        std::fprintf(stderr, "\rframe %d/%d  %.2f ms", f - resume_at + 1, end - resume_at, rec.frame_ms);
    }
    if (!quiet && end - resume_at > 1) std::fprintf(stderr, "\n");
    if (!p.has("no-trace")) write_chrome_trace(out + "/trace.json", report);
  });
  if (shard.given) {
    manifest.complete = true;
    manifest.extra = {{"warmup_frames", warm}};
    write_shard_manifest(out, manifest);
  }
  if (!quiet) {
    std::cout << format_summary(report);
    std::cout << "wrote " << out << "/" << (png ? "frame_*.png " : "") << (exr ? "frame_*.exr " : "")
              << "report.json" << (p.has("no-trace") ? "" : " trace.json") << "\n";
  }
  return 0;
}

}  // namespace cr
