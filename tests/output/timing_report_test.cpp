#include <doctest/doctest.h>

#include "engine/output/atomic_file.h"
#include "engine/output/percentile.h"
#include "engine/output/timing_report.h"
#include "tests/output/scratch_dir.h"

using cr::test::ScratchDir;

namespace {

// 100 frames of 1..100 ms; "geometry" takes 60% of each frame, "sky.lut"
// runs every 4th frame for 2 ms. Frame k starts at k * 1000 ms.
cr::RunReport hundred_frames() {
  cr::RunReport report;
  report.scene = "test-scene";
  report.profile = "desktop";
  report.width = 320;
  report.height = 180;
  report.threads = 2;
  report.frame_budget_ms = 33.3;
  for (int f = 0; f < 100; ++f) {
    cr::FrameTiming frame;
    frame.frame = f;
    frame.begin_us = f * 1e6;
    frame.frame_ms = f + 1;
    const double geometry_us = 0.6 * frame.frame_ms * 1e3;
    frame.passes.push_back({"geometry", frame.begin_us, frame.begin_us + geometry_us});
    if (f % 4 == 0) frame.passes.push_back({"sky.lut", frame.begin_us, frame.begin_us + 2000.0});
    frame.culled = {"fog"};
    report.frames.push_back(frame);
  }
  return report;
}

}  // namespace

TEST_CASE("nearest-rank percentiles") {
  std::vector<double> samples;
  for (int i = 100; i >= 1; --i) samples.push_back(i);  // order must not matter
  CHECK(cr::percentile_nearest_rank(samples, 50) == 50);
  CHECK(cr::percentile_nearest_rank(samples, 95) == 95);
  CHECK(cr::percentile_nearest_rank(samples, 99) == 99);
  CHECK(cr::percentile_nearest_rank(samples, 100) == 100);
  CHECK(cr::percentile_nearest_rank(samples, 0) == 1);
  CHECK(cr::percentile_nearest_rank({7.0}, 99) == 7.0);
  CHECK(cr::percentile_nearest_rank({1, 2, 3, 4}, 50) == 2);   // rank ceil(2) = 2
  CHECK(cr::percentile_nearest_rank({1, 2, 3, 4}, 51) == 3);   // rank ceil(2.04) = 3
  CHECK(cr::percentile_nearest_rank({}, 50) == 0);
}

TEST_CASE("report summary: frame percentiles, budget overruns, per-pass statistics") {
  const nlohmann::json doc = cr::report_to_json(hundred_frames());
  const nlohmann::json& summary = doc["summary"];
  CHECK(summary["frames"] == 100);
  CHECK(summary["frame_ms"]["p50"] == 50.0);
  CHECK(summary["frame_ms"]["p95"] == 95.0);
  CHECK(summary["frame_ms"]["p99"] == 99.0);
  CHECK(summary["frame_ms"]["max"] == 100.0);
  CHECK(summary["frame_ms"]["mean"].get<double>() == doctest::Approx(50.5));
  CHECK(summary["frame_budget_ms"] == 33.3);
  CHECK(summary["frames_over_budget"] == 67);  // 34..100 ms
  CHECK(summary["percentile_method"].get<std::string>().find("nearest-rank") == 0);

  REQUIRE(summary["passes"].size() == 2);
  const nlohmann::json& geometry = summary["passes"][0];
  CHECK(geometry["name"] == "geometry");
  CHECK(geometry["frames_run"] == 100);
  CHECK(geometry["p50"].get<double>() == doctest::Approx(30.0));
  CHECK(geometry["p95"].get<double>() == doctest::Approx(57.0));
  CHECK(geometry["max"].get<double>() == doctest::Approx(60.0));
  const nlohmann::json& lut = summary["passes"][1];
  CHECK(lut["name"] == "sky.lut");
  CHECK(lut["frames_run"] == 25);
  CHECK(lut["mean_when_run"].get<double>() == doctest::Approx(2.0));
  CHECK(lut["amortized_ms"].get<double>() == doctest::Approx(0.5));

  REQUIRE(doc["frames"].size() == 100);
  CHECK(doc["frames"][40]["over_budget"] == true);
  CHECK(doc["frames"][10]["over_budget"] == false);
  CHECK(doc["frames"][0]["culled"] == nlohmann::json::array({"fog"}));
  CHECK(doc["resolution"]["width"] == 320);
}

TEST_CASE("job statistics count nested jobs once per worker") {
  cr::RunReport report;
  report.threads = 3;
  cr::FrameTiming frame;
  frame.frame_ms = 10.0;
  // Worker 0 runs a pass job 0..8 ms and, nested inside, loop chunks 1..3 and 2..4 ms.
  frame.jobs = {{"pass", 0, 0.0, 8000.0},
                {"chunk", 0, 1000.0, 3000.0},
                {"chunk", 0, 2000.0, 4000.0},
                {"chunk", 1, 1000.0, 2000.0},
                {"chunk", 1, 5000.0, 5500.0}};
  report.frames.push_back(frame);
  const nlohmann::json jobs = cr::report_to_json(report)["frames"][0]["jobs"];
  CHECK(jobs["count"] == 5);
  CHECK(jobs["total_job_ms"].get<double>() == doctest::Approx(8.0 + 2.0 + 2.0 + 1.0 + 0.5));
  REQUIRE(jobs["per_worker"].size() == 3);  // idle worker 2 listed too
  CHECK(jobs["per_worker"][0]["busy_ms"].get<double>() == doctest::Approx(8.0));
  CHECK(jobs["per_worker"][0]["jobs"] == 3);
  CHECK(jobs["per_worker"][1]["busy_ms"].get<double>() == doctest::Approx(1.5));
  CHECK(jobs["per_worker"][2]["busy_ms"].get<double>() == 0.0);
  CHECK(jobs["busy_ms"].get<double>() == doctest::Approx(9.5));
}

TEST_CASE("report JSON file and terminal summary") {
  ScratchDir dir("report");
  const cr::RunReport report = hundred_frames();
  cr::write_report_json(dir.file("report.json"), report);
  const nlohmann::json doc = nlohmann::json::parse(cr::read_file_bytes(dir.file("report.json")));
  CHECK(doc["format"] == "cpurender-run-report");
  CHECK(dir.entries() == std::vector<std::string>{"report.json"});

  const std::string text = cr::format_summary(report);
  CHECK(text.find("frames 100") != std::string::npos);
  CHECK(text.find("p50 50.00") != std::string::npos);
  CHECK(text.find("p99 99.00") != std::string::npos);
  CHECK(text.find("67 of 100 frames over") != std::string::npos);
  // Sorted by median cost: geometry (30 ms) before sky.lut (2 ms).
  CHECK(text.find("geometry") < text.find("sky.lut"));
}
