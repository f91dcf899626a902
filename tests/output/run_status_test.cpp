// report.json as a record of how far a run got: "running" while the work
// runs, then "complete" or "failed: <message>", each written atomically.
#include <doctest/doctest.h>

#include <filesystem>
#include <stdexcept>

#include "engine/core/error.h"
#include "engine/output/atomic_file.h"
#include "engine/output/run_status.h"
#include "tests/output/scratch_dir.h"

using cr::test::ScratchDir;

namespace {

nlohmann::json read_json(const std::string& path) { return nlohmann::json::parse(cr::read_file_bytes(path)); }

cr::FrameTiming frame(int index) {
  cr::FrameTiming f;
  f.frame = index;
  f.frame_ms = 1.0;
  return f;
}

}  // namespace

TEST_CASE("a report made after the fact says complete") {
  CHECK(cr::report_to_json(cr::RunReport{})["status"] == "complete");
}

TEST_CASE("report_run: running before the work, complete with its frames after it") {
  ScratchDir dir("status-complete");
  const std::string path = dir.file("report.json");
  cr::RunReport report;
  nlohmann::json seen_during_work;
  cr::report_run(path, report, [&] {
    seen_during_work = read_json(path);
    report.frames.push_back(frame(0));
  });
  CHECK(seen_during_work["status"] == "running");
  CHECK(seen_during_work["frames"].empty());
  const nlohmann::json done = read_json(path);
  CHECK(done["status"] == "complete");
  CHECK(done["frames"].size() == 1);
  CHECK(dir.entries() == std::vector<std::string>{"report.json"});
}

TEST_CASE("report_run: a throwing run leaves failed: <message> with its frames and rethrows") {
  ScratchDir dir("status-failed");
  const std::string path = dir.file("report.json");
  cr::RunReport report;
  CHECK_THROWS_WITH_AS(cr::report_run(path, report,
                                      [&] {
                                        report.frames.push_back(frame(0));
                                        throw std::runtime_error("frame_0001.png: disk full");
                                      }),
                       "frame_0001.png: disk full", std::runtime_error);
  const nlohmann::json failed = read_json(path);
  CHECK(failed["status"] == "failed: frame_0001.png: disk full");
  CHECK(failed["frames"].size() == 1);
}

TEST_CASE("report_run: the run's error wins over a failure to write the failed report") {
  ScratchDir dir("status-unwritable");
  const std::string out = dir.file("out");
  std::filesystem::create_directory(out);
  cr::RunReport report;
  CHECK_THROWS_WITH_AS(cr::report_run(out + "/report.json", report,
                                      [&] {
                                        std::filesystem::remove_all(out);
                                        throw std::runtime_error("output folder vanished");
                                      }),
                       "output folder vanished", std::runtime_error);
  CHECK(report.status == "failed: output folder vanished");
}

TEST_CASE("report_run: no report can be written, so nothing runs") {
  ScratchDir dir("status-nowhere");
  cr::RunReport report;
  bool ran = false;
  CHECK_THROWS_AS(cr::report_run(dir.file("missing/report.json"), report, [&] { ran = true; }), cr::Error);
  CHECK_FALSE(ran);
}
