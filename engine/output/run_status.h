#pragma once
// A run's report.json as a record of how far the run got (RunReport::status):
// "running" before the work, "complete" after it, "failed: <message>" when it
// throws, each written atomically over the last, so a tool reading the folder
// can tell a finished run from a failed or interrupted one.
#include <functional>
#include <string>

#include "engine/output/timing_report.h"

namespace cr {

// Writes `report` to `path` as "running", runs `work` (which fills the report
// in), then writes it as "complete". If `work` throws, writes it as
// "failed: <what()>" and rethrows the exception unchanged; a failure to write
// that last report is dropped so the run's own error is the one reported.
// Throws cr::Error (and runs nothing) when the first report cannot be written.
void report_run(const std::string& path, RunReport& report, const std::function<void()>& work);

}  // namespace cr
