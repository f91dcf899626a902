#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <set>

#include "engine/output/atomic_file.h"
#include "engine/output/chrome_trace.h"
#include "tests/output/scratch_dir.h"

using cr::test::ScratchDir;

namespace {

cr::RunReport two_frames() {
  cr::RunReport report;
  report.scene = "s";
  report.profile = "p";
  report.threads = 3;
  for (int f = 0; f < 2; ++f) {
    cr::FrameTiming frame;
    frame.frame = f;
    frame.begin_us = f * 20000.0;
    frame.frame_ms = 15.0;
    // Two concurrent passes, then a third.
    frame.passes = {{"shadow", frame.begin_us, frame.begin_us + 5000.0},
                    {"sky", frame.begin_us + 1000.0, frame.begin_us + 4000.0},
                    {"shade", frame.begin_us + 5000.0, frame.begin_us + 15000.0}};
    frame.jobs = {{"shadow", 0, frame.begin_us, frame.begin_us + 5000.0},
                  {"shadow.rows", 0, frame.begin_us + 100.123, frame.begin_us + 900.456},
                  {"sky", 1, frame.begin_us + 1000.0, frame.begin_us + 4000.0},
                  {"shade.tiles", 2, frame.begin_us + 5000.0, frame.begin_us + 15000.0}};
    report.frames.push_back(frame);
  }
  return report;
}

}  // namespace

TEST_CASE("chrome trace: one X event per job, rows named, valid JSON") {
  ScratchDir dir("trace");
  const cr::RunReport report = two_frames();
  cr::write_chrome_trace(dir.file("trace.json"), report);
  const nlohmann::json doc = nlohmann::json::parse(cr::read_file_bytes(dir.file("trace.json")));
  REQUIRE(doc["traceEvents"].is_array());

  std::map<int, std::string> thread_names;
  std::multiset<std::string> job_names;
  std::map<std::string, std::set<int>> pass_rows;
  int frame_events = 0;
  for (const auto& event : doc["traceEvents"]) {
    CHECK(event["pid"] == 1);
    if (event["ph"] == "M" && event["name"] == "thread_name")
      thread_names[event["tid"].get<int>()] = event["args"]["name"].get<std::string>();
    if (event["ph"] != "X") continue;
    CHECK(event["dur"].get<double>() >= 0.0);
    if (event["cat"] == "job") job_names.insert(event["name"].get<std::string>());
    if (event["cat"] == "pass") pass_rows[event["name"]].insert(event["tid"].get<int>());
    if (event["cat"] == "frame") ++frame_events;
  }
  CHECK(job_names.size() == 8);
  CHECK(job_names.count("shadow.rows") == 2);
  CHECK(frame_events == 2);
  CHECK(thread_names.at(1) == "main");  // worker 0 -> tid 1
  CHECK(thread_names.at(2) == "worker 1");
  CHECK(thread_names.at(3) == "worker 2");
  CHECK(thread_names.count(0) == 0);
  // The overlapping passes shadow and sky are on different rows.
  CHECK(*pass_rows["shadow"].begin() != *pass_rows["sky"].begin());
  CHECK(thread_names.at(*pass_rows["shadow"].begin()) == "passes");
  CHECK(thread_names.at(*pass_rows["sky"].begin()) == "passes 2");
}

TEST_CASE("chrome trace timestamps truncate to whole nanoseconds, keeping nesting") {
  const nlohmann::json doc = cr::chrome_trace_json(two_frames());
  for (const auto& event : doc["traceEvents"]) {
    if (event["ph"] != "X" || event["name"] != "shadow.rows") continue;
    // Perfetto: ns = trunc(us * 1000).
    const auto ts_ns = static_cast<long long>(event["ts"].get<double>() * 1000.0);
    const auto dur_ns = static_cast<long long>(event["dur"].get<double>() * 1000.0);
    CHECK(ts_ns % 20000000 == 100123);
    CHECK(dur_ns == 800333);
  }
}
