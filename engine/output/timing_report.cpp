#include "engine/output/timing_report.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <numeric>
#include <utility>

#include "engine/output/atomic_file.h"
#include "engine/output/percentile.h"

namespace cr {
namespace {

constexpr const char* kPercentileMethod =
    "nearest-rank: the smallest sample with at least p% of samples <= it "
    "(1-based rank ceil(p/100*n)), no interpolation";

// Total length of the union of [begin, end) intervals, in ms.
double union_ms(std::vector<std::pair<double, double>> intervals) {
  std::sort(intervals.begin(), intervals.end());
  double total_us = 0.0;
  double open_begin = 0.0, open_end = 0.0;
  bool open = false;
  for (const auto& [begin, end] : intervals) {
    if (open && begin <= open_end) {
      open_end = std::max(open_end, end);
      continue;
    }
    if (open) total_us += open_end - open_begin;
    open_begin = begin;
    open_end = end;
    open = true;
  }
  if (open) total_us += open_end - open_begin;
  return total_us * 1e-3;
}

struct JobStats {
  size_t count = 0;
  double total_ms = 0.0;                         // sum of job durations
  std::vector<double> busy_ms;                   // per worker
  std::vector<size_t> jobs_per_worker;
  double busy_total_ms() const { return std::accumulate(busy_ms.begin(), busy_ms.end(), 0.0); }
};

JobStats job_stats(const FrameTiming& frame, unsigned threads) {
  uint32_t workers = std::max(1u, threads);
  for (const JobRecord& job : frame.jobs) workers = std::max(workers, job.worker + 1);
  std::vector<std::vector<std::pair<double, double>>> intervals(workers);
  JobStats stats;
  stats.jobs_per_worker.assign(workers, 0);
  for (const JobRecord& job : frame.jobs) {
    intervals[job.worker].emplace_back(job.begin_us, job.end_us);
    stats.total_ms += (job.end_us - job.begin_us) * 1e-3;
    ++stats.jobs_per_worker[job.worker];
  }
  stats.count = frame.jobs.size();
  for (auto& worker_intervals : intervals) stats.busy_ms.push_back(union_ms(std::move(worker_intervals)));
  return stats;
}

nlohmann::json distribution(const std::vector<double>& samples) {
  const double sum = std::accumulate(samples.begin(), samples.end(), 0.0);
  return {
      {"min", samples.empty() ? 0.0 : *std::min_element(samples.begin(), samples.end())},
      {"mean", samples.empty() ? 0.0 : sum / static_cast<double>(samples.size())},
      {"p50", percentile_nearest_rank(samples, 50)},
      {"p95", percentile_nearest_rank(samples, 95)},
      {"p99", percentile_nearest_rank(samples, 99)},
      {"max", samples.empty() ? 0.0 : *std::max_element(samples.begin(), samples.end())},
  };
}

nlohmann::json frame_to_json(const FrameTiming& frame, const RunReport& report) {
  nlohmann::json passes = nlohmann::json::array();
  for (const PassTiming& pass : frame.passes) {
    passes.push_back({{"name", pass.name},
                      {"ms", pass.ms()},
                      {"start_ms", (pass.begin_us - frame.begin_us) * 1e-3}});
  }
  const JobStats stats = job_stats(frame, report.threads);
  nlohmann::json workers = nlohmann::json::array();
  for (size_t w = 0; w < stats.busy_ms.size(); ++w) {
    workers.push_back(
        {{"worker", w}, {"jobs", stats.jobs_per_worker[w]}, {"busy_ms", stats.busy_ms[w]}});
  }
  return {
      {"frame", frame.frame},
      {"frame_ms", frame.frame_ms},
      {"over_budget", report.frame_budget_ms > 0.0 && frame.frame_ms > report.frame_budget_ms},
      {"passes", passes},
      {"culled", frame.culled},
      {"jobs",
       {{"count", stats.count},
        {"total_job_ms", stats.total_ms},
        {"busy_ms", stats.busy_total_ms()},
        {"per_worker", workers}}},
      {"plugins", frame.plugins},
  };
}

std::string format_ms(double ms) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2f", ms);
  return buffer;
}

}  // namespace

std::string compiler_description() {
#if defined(__clang__)
  return std::string("Clang ") + __clang_version__;
#elif defined(__GNUC__)
  return "GCC " + std::to_string(__GNUC__) + "." + std::to_string(__GNUC_MINOR__) + "." +
         std::to_string(__GNUC_PATCHLEVEL__);
#else
  return "unknown compiler";
#endif
}

namespace {

// The report's frames: the resumed run's, then this run's.
nlohmann::json frames_json(const RunReport& report) {
  nlohmann::json frames = nlohmann::json::array();
  for (const nlohmann::json& frame : report.resumed_frames) frames.push_back(frame);
  for (const FrameTiming& frame : report.frames) frames.push_back(frame_to_json(frame, report));
  return frames;
}

}  // namespace

nlohmann::json summarize_frames(const nlohmann::json& frames, double frame_budget_ms) {
  std::vector<double> frame_ms;
  double busy_ms = 0.0, available_ms = 0.0;
  size_t jobs = 0, over = 0;
  // Per-pass samples in order of first appearance (frames may run different
  // pass sets, e.g. a LUT updated every few frames).
  std::vector<std::pair<std::string, std::vector<double>>> pass_samples;
  std::map<std::string, size_t> index;
  for (const nlohmann::json& frame : frames) {
    const double ms = frame.at("frame_ms").get<double>();
    frame_ms.push_back(ms);
    over += frame_budget_ms > 0.0 && ms > frame_budget_ms;
    const nlohmann::json& j = frame.at("jobs");
    jobs += j.at("count").get<size_t>();
    busy_ms += j.at("busy_ms").get<double>();
    available_ms += ms * double(std::max<size_t>(1, j.at("per_worker").size()));
    for (const nlohmann::json& pass : frame.at("passes")) {
      const std::string name = pass.at("name").get<std::string>();
      auto [it, inserted] = index.emplace(name, pass_samples.size());
      if (inserted) pass_samples.emplace_back(name, std::vector<double>{});
      pass_samples[it->second].second.push_back(pass.at("ms").get<double>());
    }
  }
  const double frame_count = static_cast<double>(frame_ms.size());
  nlohmann::json passes = nlohmann::json::array();
  for (const auto& [name, samples] : pass_samples) {
    const double sum = std::accumulate(samples.begin(), samples.end(), 0.0);
    passes.push_back({{"name", name},
                      {"frames_run", samples.size()},
                      {"p50", percentile_nearest_rank(samples, 50)},
                      {"p95", percentile_nearest_rank(samples, 95)},
                      {"max", *std::max_element(samples.begin(), samples.end())},
                      {"mean_when_run", sum / static_cast<double>(samples.size())},
                      // Amortised: total cost spread over every frame, for passes run periodically.
                      {"amortized_ms", frame_count > 0 ? sum / frame_count : 0.0}});
  }
  return {
      {"frames", frame_ms.size()},
      {"percentile_method", kPercentileMethod},
      {"frame_ms", distribution(frame_ms)},
      {"frame_budget_ms", frame_budget_ms},
      {"frames_over_budget", over},
      {"over_budget_fraction", frame_count > 0 ? static_cast<double>(over) / frame_count : 0.0},
      {"passes", passes},
      {"jobs",
       {{"mean_per_frame", frame_count > 0 ? static_cast<double>(jobs) / frame_count : 0.0},
        // Busy worker time over (frame time x threads): 1 = every thread always busy.
        {"utilization", available_ms > 0 ? busy_ms / available_ms : 0.0}}},
  };
}

nlohmann::json report_to_json(const RunReport& report) {
  const nlohmann::json frames = frames_json(report);
  return {
      {"format", "cpurender-run-report"},
      {"version", 1},
      {"status", report.status},
      {"scene", report.scene},
      {"profile", report.profile},
      {"resolution", {{"width", report.width}, {"height", report.height}}},
      {"threads", report.threads},
      {"build",
       {{"compiler", report.build.compiler},
        {"build_type", report.build.build_type},
        {"flags", report.build.flags}}},
      {"summary", summarize_frames(frames, report.frame_budget_ms)},
      {"frames", frames},
      {"extra", report.extra},
  };
}

void write_report_json(const std::string& path, const RunReport& report) {
  write_file_atomic(path, report_to_json(report).dump(2) + "\n");
}

std::string format_summary(const RunReport& report) { return format_summary(report_to_json(report)); }

std::string format_summary(const nlohmann::json& report) {
  const nlohmann::json& summary = report.at("summary");
  const nlohmann::json& ms = summary.at("frame_ms");
  const size_t frames = summary.at("frames").get<size_t>();
  std::string out;
  char line[256];
  std::snprintf(line, sizeof line, "%s | %s | %dx%d | %u threads\n", report.at("scene").get<std::string>().c_str(),
                report.at("profile").get<std::string>().c_str(), report.at("resolution").at("width").get<int>(),
                report.at("resolution").at("height").get<int>(), report.at("threads").get<unsigned>());
  out += line;
  std::snprintf(line, sizeof line, "frames %zu  frame ms: p50 %s  p95 %s  p99 %s  max %s\n", frames,
                format_ms(ms.at("p50").get<double>()).c_str(), format_ms(ms.at("p95").get<double>()).c_str(),
                format_ms(ms.at("p99").get<double>()).c_str(), format_ms(ms.at("max").get<double>()).c_str());
  out += line;
  const double budget = summary.at("frame_budget_ms").get<double>();
  if (budget > 0.0) {
    std::snprintf(line, sizeof line, "budget %s ms: %zu of %zu frames over\n", format_ms(budget).c_str(),
                  summary.at("frames_over_budget").get<size_t>(), frames);
    out += line;
  }
  std::vector<nlohmann::json> passes(summary.at("passes").begin(), summary.at("passes").end());
  std::stable_sort(passes.begin(), passes.end(), [](const nlohmann::json& a, const nlohmann::json& b) {
    return a.at("p50").get<double>() > b.at("p50").get<double>();
  });
  if (!passes.empty()) {
    std::snprintf(line, sizeof line, "%-28s %10s %10s %10s %8s\n", "pass", "median ms", "p95 ms", "max ms", "frames");
    out += line;
  }
  for (const nlohmann::json& pass : passes) {
    std::snprintf(line, sizeof line, "%-28s %10s %10s %10s %8zu\n", pass.at("name").get<std::string>().c_str(),
                  format_ms(pass.at("p50").get<double>()).c_str(), format_ms(pass.at("p95").get<double>()).c_str(),
                  format_ms(pass.at("max").get<double>()).c_str(), pass.at("frames_run").get<size_t>());
    out += line;
  }
  return out;
}

}  // namespace cr
