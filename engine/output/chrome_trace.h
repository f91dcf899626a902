#pragma once
// Chrome Trace Event Format output ({"traceEvents": [...]}) of a run's jobs,
// passes and frames, for ui.perfetto.dev or chrome://tracing.
//
// Rows (pid 1): one per worker thread ("main" = worker 0, "worker N"), with
// every job as a complete ("X") event; a "frames" row with one event per
// frame; and "passes" rows with one event per executed pass (concurrent
// passes go to extra rows "passes 2", ... so events on a row never overlap).
// Thread ids are worker + 1: Perfetto's JSON importer merged tid 0 into tid 1
// (thoren-d/tracing-chrome#32), so tid 0 is never used.
#include <string>

#include <nlohmann/json.hpp>

#include "engine/output/timing_report.h"

namespace cr {

nlohmann::json chrome_trace_json(const RunReport& report);

// chrome_trace_json written atomically. Throws cr::Error.
void write_chrome_trace(const std::string& path, const RunReport& report);

}  // namespace cr
