#include "engine/output/run_status.h"

#include <exception>

namespace cr {

void report_run(const std::string& path, RunReport& report, const std::function<void()>& work) {
  report.status = "running";
  write_report_json(path, report);
  try {
    work();
  } catch (const std::exception& e) {
    report.status = std::string("failed: ") + e.what();
    try {
      write_report_json(path, report);
    } catch (const std::exception&) {
      // A folder that refused this report most likely caused the error itself.
    }
    throw;
  }
  report.status = "complete";
  write_report_json(path, report);
}

}  // namespace cr
