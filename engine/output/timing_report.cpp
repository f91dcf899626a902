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

// Per-pass samples in order of first appearance (frames may run different
// pass sets, e.g. a LUT updated every few frames).
std::vector<std::pair<std::string, std::vector<double>>> pass_samples(const RunReport& report) {
  std::vector<std::pair<std::string, std::vector<double>>> passes;
  std::map<std::string, size_t> index;
  for (const FrameTiming& frame : report.frames) {
    for (const PassTiming& pass : frame.passes) {
      auto [it, inserted] = index.emplace(pass.name, passes.size());
      if (inserted) passes.emplace_back(pass.name, std::vector<double>{});
      passes[it->second].second.push_back(pass.ms());
    }
  }
  return passes;
}

size_t frames_over_budget(const RunReport& report) {
  if (report.frame_budget_ms <= 0.0) return 0;
  return static_cast<size_t>(std::count_if(
      report.frames.begin(), report.frames.end(),
      [&](const FrameTiming& f) { return f.frame_ms > report.frame_budget_ms; }));
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

nlohmann::json summary_to_json(const RunReport& report) {
  std::vector<double> frame_ms;
  double busy_ms = 0.0, available_ms = 0.0;
  size_t jobs = 0;
  for (const FrameTiming& frame : report.frames) {
    frame_ms.push_back(frame.frame_ms);
    const JobStats stats = job_stats(frame, report.threads);
    jobs += stats.count;
    busy_ms += stats.busy_total_ms();
    available_ms += frame.frame_ms * std::max(1u, report.threads);
  }
  const double frame_count = static_cast<double>(report.frames.size());
  nlohmann::json passes = nlohmann::json::array();
  for (const auto& [name, samples] : pass_samples(report)) {
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
  const size_t over = frames_over_budget(report);
  return {
      {"frames", report.frames.size()},
      {"percentile_method", kPercentileMethod},
      {"frame_ms", distribution(frame_ms)},
      {"frame_budget_ms", report.frame_budget_ms},
      {"frames_over_budget", over},
      {"over_budget_fraction", frame_count > 0 ? static_cast<double>(over) / frame_count : 0.0},
      {"passes", passes},
      {"jobs",
       {{"mean_per_frame", frame_count > 0 ? static_cast<double>(jobs) / frame_count : 0.0},
        // Busy worker time over (frame time x threads): 1 = every thread always busy.
        {"utilization", available_ms > 0 ? busy_ms / available_ms : 0.0}}},
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

nlohmann::json report_to_json(const RunReport& report) {
  nlohmann::json frames = nlohmann::json::array();
  for (const FrameTiming& frame : report.frames) frames.push_back(frame_to_json(frame, report));
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
      {"summary", summary_to_json(report)},
      {"frames", frames},
      {"extra", report.extra},
  };
}

void write_report_json(const std::string& path, const RunReport& report) {
  write_file_atomic(path, report_to_json(report).dump(2) + "\n");
}

std::string format_summary(const RunReport& report) {
  std::vector<double> frame_ms;
  for (const FrameTiming& frame : report.frames) frame_ms.push_back(frame.frame_ms);
  std::string out;
  char line[256];
  std::snprintf(line, sizeof line, "%s | %s | %dx%d | %u threads\n", report.scene.c_str(),
                report.profile.c_str(), report.width, report.height, report.threads);
  out += line;
  std::snprintf(line, sizeof line, "frames %zu  frame ms: p50 %s  p95 %s  p99 %s  max %s\n",
                frame_ms.size(), format_ms(percentile_nearest_rank(frame_ms, 50)).c_str(),
                format_ms(percentile_nearest_rank(frame_ms, 95)).c_str(),
                format_ms(percentile_nearest_rank(frame_ms, 99)).c_str(),
                format_ms(frame_ms.empty() ? 0.0 : *std::max_element(frame_ms.begin(), frame_ms.end()))
                    .c_str());
  out += line;
  if (report.frame_budget_ms > 0.0) {
    std::snprintf(line, sizeof line, "budget %s ms: %zu of %zu frames over\n",
                  format_ms(report.frame_budget_ms).c_str(), frames_over_budget(report),
                  frame_ms.size());
    out += line;
  }
  auto passes = pass_samples(report);
  std::vector<std::pair<double, size_t>> order;
  for (size_t i = 0; i < passes.size(); ++i)
    order.emplace_back(percentile_nearest_rank(passes[i].second, 50), i);
  std::stable_sort(order.begin(), order.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  if (!passes.empty()) {
    std::snprintf(line, sizeof line, "%-28s %10s %10s %10s %8s\n", "pass", "median ms", "p95 ms",
                  "max ms", "frames");
    out += line;
  }
  for (const auto& [median, i] : order) {
    const auto& [name, samples] = passes[i];
    std::snprintf(line, sizeof line, "%-28s %10s %10s %10s %8zu\n", name.c_str(),
                  format_ms(median).c_str(),
                  format_ms(percentile_nearest_rank(samples, 95)).c_str(),
                  format_ms(*std::max_element(samples.begin(), samples.end())).c_str(),
                  samples.size());
    out += line;
  }
  return out;
}

}  // namespace cr
