#include "engine/cli/golden_command.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "engine/cli/arg_parser.h"
#include "engine/cli/cache_key.h"
#include "engine/cli/cli_common.h"
#include "engine/cli/golden_cases.h"
#include "engine/cli/golden_render.h"
#include "engine/cli/golden_report.h"
#include "engine/cli/golden_tolerances.h"
#include "engine/cli/paths.h"
#include "engine/cli/shard.h"
#include "engine/core/error.h"
#include "engine/output/atomic_file.h"
#include "engine/output/png_io.h"

namespace cr {

namespace fs = std::filesystem;

namespace {

constexpr const char* kDescription =
    "Renders every scene (*.json in --scenes) under every profile (*.json in --profiles) at a small\n"
    "resolution: scenes with a camera path or plugin sections render frames 0..8 (or to their last\n"
    "frame) in order and keep frames 0 and the last; others keep frame 0. Each case renders with 1\n"
    "thread and with --threads threads; every buffer of every frame must be bit-identical. Kept frames\n"
    "are compared with DIR/<scene>.<profile>.fNNNN.png under the profile's tolerances (--tolerances).\n"
    "The report (golden_report.json, golden_report.txt) and, for failures, difference heat maps and\n"
    "the new render go to --report.\n"
    "--update renders everything first and writes nothing if a case fails to render or differs\n"
    "between thread counts; otherwise it adds missing goldens and rewrites those that fail their\n"
    "tolerances (with --exact: every golden whose pixels changed), printing the metrics against the\n"
    "old golden. Goldens no case produces are listed as stale (deleted with --update --prune).\n"
    "A check records each case in REPORT/cases/ as it finishes; --resume keeps those of an earlier run\n"
    "of the same check (same build, cases and inputs). --shard I/N checks only the cases k with\n"
    "k mod N = I and writes REPORT/shard.json; `cpurender merge` joins the shards' reports.\n"
    "Exit status: 0 pass, 1 a case failed, 2 usage error or a case could not be rendered.";

ImageRGBf to_display_rgb(const Image8& image) {
  ImageRGBf rgb(image.width, image.height);
  for (size_t i = 0; i < image.data.size(); ++i) rgb.rgb[i] = image.data[i] / 255.0f;
  return rgb;
}

// A kept frame against its golden file, as far as the two can be compared.
struct GoldenComparison {
  bool golden_exists = false;
  std::optional<CompareResult> result;  // absent when missing, unreadable or resized
  std::string problem;                  // why there is no result
};

GoldenComparison compare_with_golden(const std::string& golden_path, const Image8& render,
                                     const CompareThresholds& thresholds) {
  GoldenComparison c;
  std::error_code ec;
  c.golden_exists = fs::exists(golden_path, ec);
  if (!c.golden_exists) {
    c.problem = "no golden image: run `cpurender golden --update` and review it";
    return c;
  }
  Image8 golden;
  try {
    golden = read_png(golden_path, 3);
  } catch (const InputError& e) {
    c.problem = std::string("golden unreadable: ") + e.what();
    return c;
  }
  if (golden.width != render.width || golden.height != render.height) {
    c.problem = "golden is " + std::to_string(golden.width) + "x" + std::to_string(golden.height) +
                ", render is " + std::to_string(render.width) + "x" + std::to_string(render.height);
    return c;
  }
  c.result = compare_images(to_display_rgb(golden), to_display_rgb(render), ImageEncoding::Display, thresholds);
  return c;
}

std::string stem_of(const std::string& png_name) { return png_name.substr(0, png_name.size() - 4); }

// Heat maps (max channel difference scaled to its maximum, and FLIP) and
// the new render beside them, so a reviewer sees old, new and where they differ.
void write_review_images(GoldenRow& row, const std::string& report_dir, const std::string& stem,
                         const std::optional<CompareResult>& result, const Image8& render, bool write_render) {
  if (result) {
    row.diff_image = report_dir + "/" + stem + ".diff.png";
    row.flip_image = report_dir + "/" + stem + ".flip.png";
    write_error_heatmap(row.diff_image, *result, HeatmapKind::Difference);
    write_error_heatmap(row.flip_image, *result, HeatmapKind::Flip);
  }
  if (write_render) {
    row.new_image = report_dir + "/" + stem + ".new.png";
    write_png(row.new_image, render);
  }
}

struct RenderedCase {
  GoldenCase golden_case;
  std::optional<GoldenRender> render;
  std::string error;
};

}  // namespace

int golden_command(const std::vector<std::string>& args, const PluginRegistry& registry) {
  ArgParser p("golden", "cpurender golden [options]", kDescription);
  p.option("dir", "DIR", "golden images", "tests/golden")
      .option("tolerances", "FILE", "per-profile thresholds (default: DIR/tolerances.json)")
      .option("report", "DIR", "report and review images", "out/golden")
      .option("only", "PATTERN", "only cases whose \"<scene>.<profile>\" matches this shell glob")
      .option("threads", "N", "threads of the multi-thread render, >= 2 (default: all cores, at least 3)")
      .option("resolution", "WxH", "render size of every case", "320x180")
      .option("scenes", "DIR", "scene files (default: the shipped scenes beside the executable)")
      .option("profiles", "DIR", "profile files (default: the shipped profiles beside the executable)")
      .flag("update", "add missing goldens and rewrite those that fail their tolerances")
      .flag("exact", "with --update: rewrite every golden whose pixels changed")
      .flag("prune", "with --update: delete stale goldens")
      .flag("resume", "check: keep the cases an earlier run of the same check finished (REPORT/cases/)");
  add_shard_option(p);
  if (!p.parse(args, 0, 0)) return 0;
  const bool update = p.has("update");
  const ShardOption shard = shard_option(p, "golden");
  if (update && (shard.given || p.has("resume")))
    throw UsageError("golden: --update renders every case in one run (it writes no golden unless all render and are "
                     "deterministic); --shard and --resume are for checks");
  if (!update && (p.has("exact") || p.has("prune"))) throw UsageError("golden: --exact and --prune need --update");
  const auto [width, height] = parse_resolution(p.get("resolution"), "golden");
  const unsigned threads = p.has("threads") ? unsigned(p.get_int("threads", 2, 1024))
                                            : std::max(3u, JobSystem::default_thread_count());
  const std::string dir = p.get("dir");
  const std::string report_dir = p.get("report");
  const std::string scenes_dir = p.has("scenes") ? p.get("scenes") : executable_dir() + "/scenes";
  const std::string profiles_dir = p.has("profiles") ? p.get("profiles") : executable_dir() + "/profiles";
  const auto start = std::chrono::steady_clock::now();

  GoldenReport report;
  report.mode = update ? "update" : "check";
  report.golden_dir = dir;
  report.tolerances = p.has("tolerances") ? p.get("tolerances") : dir + "/tolerances.json";
  report.report_dir = report_dir;
  report.width = width;
  report.height = height;
  report.threads = threads;

  const GoldenTolerances tolerances = GoldenTolerances::load(report.tolerances);
  const std::vector<GoldenCase> all_cases = discover_golden_cases(scenes_dir, profiles_dir, registry.names());
  std::vector<GoldenCase> cases = all_cases;
  if (p.has("only")) {
    cases = filter_golden_cases(all_cases, p.get("only"));
    if (cases.empty()) {
      std::string names;
      for (const GoldenCase& c : all_cases) names += " " + c.name();
      throw UsageError("golden: --only '" + p.get("only") + "' matches no case; cases:" + names);
    }
  }

  // What the check is (its cases and every file they read), so a resumed
  // check or a merged shard never mixes runs of other inputs.
  nlohmann::json definition = {{"golden_dir", dir}, {"resolution", {width, height}}};
  {
    std::string inputs = read_file_bytes(report.tolerances);
    for (const GoldenCase& c : cases)
      inputs += c.name() + "|" + read_file_bytes(c.scene_path) + "|" + read_file_bytes(c.profile_path);
    definition["inputs"] = cache_name(inputs);
  }
  const std::string cases_dir = report_dir + "/cases";
  ShardManifest manifest = new_shard_manifest("golden", shard.shard, definition);
  for (size_t i = 0; i < cases.size(); ++i) {
    manifest.items.push_back(cases[i].name());
    if (shard.shard.owns(i)) manifest.owned.push_back(cases[i].name());
  }
  if (shard.given) {
    fs::create_directories(report_dir);
    write_shard_manifest(report_dir, manifest);
  }

  bool any_error = false, any_nondeterministic = false, any_fail = false;
  std::vector<std::pair<std::string, const Image8*>> to_write;  // golden path, image
  // The rows of a rendered case: compared with its goldens; in update mode,
  // what would be rewritten is queued in to_write (images owned by `rc`).
  auto case_rows = [&](const RenderedCase& rc) {
    std::vector<GoldenRow> rows;
    const GoldenCase& c = rc.golden_case;
    const GoldenTolerance tolerance = tolerances.for_profile(c.profile);
    for (size_t k = 0; k < c.kept_frames.size(); ++k) {
      GoldenRow row;
      row.case_name = c.name();
      row.scene = c.scene;
      row.profile = c.profile;
      row.frame = c.kept_frames[k];
      const std::string name = golden_file_name(c, row.frame);
      row.golden = dir + "/" + name;
      row.tolerance_entry = tolerance.entry;
      row.thresholds = tolerance.thresholds;
      row.threads = threads;
      if (!rc.render) {
        row.status = GoldenStatus::Error;
        row.failures.push_back(rc.error);
        rows.push_back(std::move(row));
        continue;
      }
      const GoldenRender& render = *rc.render;
      const Image8& image = render.kept[k].image;
      row.ms_one_thread = render.ms_one_thread;
      row.ms_threads = render.ms_threads;
      row.deterministic = render.deterministic;
      row.determinism_detail = render.determinism_detail;
      if (!render.deterministic)
        row.failures.push_back("1-thread and " + std::to_string(threads) + "-thread renders differ");

      const GoldenComparison cmp = compare_with_golden(row.golden, image, row.thresholds);
      if (cmp.result) row.metrics = cmp.result->metrics;
      const bool within = cmp.result && cmp.result->pass;
      if (cmp.result) row.failures.insert(row.failures.end(), cmp.result->failures.begin(), cmp.result->failures.end());
      else row.failures.push_back(cmp.problem);

      if (!update) {
        const bool pass = within && render.deterministic;
        row.status = pass ? GoldenStatus::Pass : GoldenStatus::Fail;
        if (!pass) write_review_images(row, report_dir, stem_of(name), cmp.result, image, true);
      } else {
        const bool identical = cmp.result && cmp.result->metrics.max_abs == 0.0;
        const bool rewrite = !within || (p.has("exact") && !identical);
        if (!render.deterministic) row.status = GoldenStatus::Fail;
        else if (!cmp.golden_exists) row.status = GoldenStatus::Added;
        else if (rewrite) row.status = GoldenStatus::Updated;
        else row.status = identical ? GoldenStatus::Unchanged : GoldenStatus::Kept;
        if (rewrite) to_write.emplace_back(row.golden, &image);
        if (row.status == GoldenStatus::Updated) write_review_images(row, report_dir, stem_of(name), cmp.result, image, false);
        // In update mode the compare failures are the reasons for a rewrite.
        if (!cmp.golden_exists) row.failures.clear();
      }
      rows.push_back(std::move(row));
    }
    return rows;
  };
  // A check's finished case: REPORT/cases/<case>.json (what --resume keeps).
  auto case_file = [&](const GoldenCase& c) { return cases_dir + "/" + c.name() + ".json"; };
  auto kept_rows = [&](const GoldenCase& c) -> std::optional<std::vector<GoldenRow>> {
    const std::string file = case_file(c);
    if (!p.has("resume") || !fs::exists(file)) return std::nullopt;
    const nlohmann::json j = nlohmann::json::parse(read_file_bytes(file), nullptr, false);
    if (j.is_discarded() || !j.is_object() || j.value("definition", nlohmann::json()) != definition ||
        j.value("build", "") != build_hash())
      return std::nullopt;  // another check's or another build's: render again
    std::vector<GoldenRow> rows;
    for (const nlohmann::json& row : j.value("rows", nlohmann::json::array()))
      rows.push_back(golden_row_from_json(row, file));
    return rows;
  };

  fs::create_directories(report_dir);
  // A check compares and records each case as it renders; an update renders
  // everything before looking at or writing any golden.
  std::vector<RenderedCase> rendered;
  size_t kept_cases = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    if (!shard.shard.owns(i)) continue;
    if (std::optional<std::vector<GoldenRow>> rows = kept_rows(cases[i])) {
      report.rows.insert(report.rows.end(), rows->begin(), rows->end());
      manifest.done.push_back(cases[i].name());
      ++kept_cases;
      continue;
    }
    RenderedCase r{cases[i], std::nullopt, ""};
    try {
      if (!cases[i].error.empty()) throw Error(cases[i].error);
      r.render = render_golden_case(cases[i], registry, width, height, threads);
      std::fprintf(stderr, "golden: [%zu/%zu] %s: frames 0..%d, %.0f ms at 1 thread, %.0f ms at %u\n", i + 1,
                   cases.size(), cases[i].name().c_str(), cases[i].last_frame, r.render->ms_one_thread,
                   r.render->ms_threads, threads);
    } catch (const std::exception& e) {
      r.error = e.what();
      std::fprintf(stderr, "golden: [%zu/%zu] %s: ERROR %s\n", i + 1, cases.size(), cases[i].name().c_str(),
                   e.what());
    }
    if (update) {
      rendered.push_back(std::move(r));
      continue;
    }
    const std::vector<GoldenRow> rows = case_rows(r);
    nlohmann::json record = {{"definition", definition}, {"build", build_hash()}, {"rows", nlohmann::json::array()}};
    for (const GoldenRow& row : rows) record["rows"].push_back(golden_row_json(row));
    fs::create_directories(cases_dir);
    write_file_atomic(case_file(cases[i]), record.dump(2) + "\n");
    report.rows.insert(report.rows.end(), rows.begin(), rows.end());
    manifest.done.push_back(cases[i].name());
    if (shard.given) write_shard_manifest(report_dir, manifest);
  }
  for (const RenderedCase& rc : rendered) {
    const std::vector<GoldenRow> rows = case_rows(rc);
    report.rows.insert(report.rows.end(), rows.begin(), rows.end());
  }
  if (kept_cases > 0) std::fprintf(stderr, "golden: %zu case(s) kept from the earlier run (--resume)\n", kept_cases);
  for (const GoldenRow& row : report.rows) {
    any_error |= row.status == GoldenStatus::Error;
    any_nondeterministic |= row.status != GoldenStatus::Error && !row.deterministic;
    any_fail |= row.status == GoldenStatus::Fail;
  }

  report.stale = find_stale_goldens(dir, all_cases);
  if (update) {
    if (any_error) {
      report.note = "nothing written: a case could not be rendered";
    } else if (any_nondeterministic) {
      report.note = "nothing written: 1-thread and multi-thread renders differ";
    } else {
      fs::create_directories(dir);
      for (const auto& [path, image] : to_write) write_png(path, *image);
      report.wrote_goldens = !to_write.empty();
      if (p.has("prune")) {
        for (const std::string& s : report.stale) fs::remove(fs::path(dir) / s);
        report.pruned = !report.stale.empty();
      }
      report.note = std::to_string(to_write.size()) + " golden(s) written";
    }
  }
  report.exit_code = any_error ? 2 : (any_fail || any_nondeterministic) ? 1 : 0;
  report.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const std::string table = format_golden_report(report);
  write_file_atomic(report_dir + "/golden_report.txt", table);
  write_file_atomic(report_dir + "/golden_report.json", golden_report_json(report).dump(2) + "\n");
  if (shard.given) {
    manifest.complete = manifest.done.size() == manifest.owned.size();
    write_shard_manifest(report_dir, manifest);
  }
  std::cout << table << "report: " << report_dir << "/golden_report.json, " << report_dir
            << "/golden_report.txt\n";
  return report.exit_code;
}

}  // namespace cr
