#pragma once
// Run reports: per-frame pass and job timings, summarised into percentiles
// and budget counts, as JSON (for tools) and as a terminal table (for people).
// Frames are FrameTimings (engine/core/frame_timing.h), the renderer's own
// records, so this layer does not depend on the renderer.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/frame_timing.h"

namespace cr {

struct BuildInfo {
  std::string compiler;    // e.g. compiler_description()
  std::string build_type;  // e.g. "Release"
  std::string flags;       // compile flags, as the caller knows them
};

struct RunReport {
  // Whether the run finished: "running" while the render command renders
  // (written before its first frame), "complete" when every frame and the
  // trace are written, "failed: <message>" when it stopped on that error
  // (`frames` then holds the frames written before it). A report left at
  // "running" is a run that was killed or is still going. A report made
  // after the fact (tests, tools) is complete.
  std::string status = "complete";
  std::string scene;
  std::string profile;
  int width = 0;
  int height = 0;
  unsigned threads = 1;
  double frame_budget_ms = 0.0;  // <= 0: no budget
  std::vector<FrameTiming> frames;
  // Frames an earlier, interrupted run of the same render wrote (render
  // --resume), as its report recorded them; listed before `frames`.
  std::vector<nlohmann::json> resumed_frames;
  BuildInfo build;
  nlohmann::json extra = nlohmann::json::object();
};

// The compiler that built this library, e.g. "GCC 12.2.0".
std::string compiler_description();

// The full report: run parameters, per-frame pass times and job statistics
// (count, summed job time, per-worker busy time as the union of that
// worker's job intervals, so nested jobs are not counted twice), and a
// summary with nearest-rank percentiles (see percentile.h) of frame and pass
// times and the number of frames over budget (frame_ms > budget).
nlohmann::json report_to_json(const RunReport& report);

// report_to_json, pretty-printed, written atomically. Throws cr::Error.
void write_report_json(const std::string& path, const RunReport& report);

// The report's "summary" from its "frames" entries (report_to_json's): frame
// and pass percentiles, budget overruns, job counts and utilisation. Also
// what a merged report of several runs' frames is summarised with.
nlohmann::json summarize_frames(const nlohmann::json& frames, double frame_budget_ms);
// A short table for the terminal: frame-time percentiles, budget overruns,
// and each pass's median / p95 / max sorted by median cost.
std::string format_summary(const RunReport& report);
std::string format_summary(const nlohmann::json& report);  // of report_to_json's document

}  // namespace cr
