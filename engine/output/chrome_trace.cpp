#include "engine/output/chrome_trace.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "engine/output/atomic_file.h"

namespace cr {
namespace {

constexpr int kPid = 1;

// Times go out as microseconds that map to whole nanoseconds. Perfetto
// converts a fractional ts to ns by truncating ts * 1000, so a value like
// 12.345 may become 12344 ns and a nested job could appear to end after its
// parent. Writing (ns + 0.5) / 1000 makes the truncation land exactly on ns.
int64_t to_ns(double us) { return std::llround(us * 1000.0); }
double ns_to_trace_us(int64_t ns) { return (static_cast<double>(ns) + 0.5) / 1000.0; }

nlohmann::json complete_event(const std::string& name, const char* category, int tid,
                              int64_t begin_ns, int64_t end_ns, nlohmann::json args) {
  return {{"name", name},
          {"cat", category},
          {"ph", "X"},
          {"pid", kPid},
          {"tid", tid},
          {"ts", ns_to_trace_us(begin_ns)},
          {"dur", ns_to_trace_us(std::max<int64_t>(0, end_ns - begin_ns))},
          {"args", std::move(args)}};
}

nlohmann::json thread_metadata(int tid, const std::string& name, int sort_index) {
  return nlohmann::json::array({
      {{"name", "thread_name"}, {"ph", "M"}, {"pid", kPid}, {"tid", tid}, {"args", {{"name", name}}}},
      {{"name", "thread_sort_index"},
       {"ph", "M"},
       {"pid", kPid},
       {"tid", tid},
       {"args", {{"sort_index", sort_index}}}},
  });
}

}  // namespace

nlohmann::json chrome_trace_json(const RunReport& report) {
  uint32_t workers = std::max(1u, report.threads);
  for (const FrameTiming& frame : report.frames)
    for (const JobRecord& job : frame.jobs) workers = std::max(workers, job.worker + 1);

  nlohmann::json events = nlohmann::json::array();
  const int frames_tid = static_cast<int>(workers) + 1;
  const int first_pass_tid = frames_tid + 1;

  // Pass rows: each pass goes to the first row whose last pass has ended.
  std::vector<int64_t> lane_end_ns;
  for (const FrameTiming& frame : report.frames) {
    const int64_t frame_begin = to_ns(frame.begin_us);
    events.push_back(complete_event("frame " + std::to_string(frame.frame), "frame", frames_tid,
                                    frame_begin, frame_begin + to_ns(frame.frame_ms * 1000.0),
                                    {{"frame", frame.frame}, {"frame_ms", frame.frame_ms}}));

    std::vector<const PassTiming*> passes;
    for (const PassTiming& pass : frame.passes) passes.push_back(&pass);
    std::stable_sort(passes.begin(), passes.end(),
                     [](const PassTiming* a, const PassTiming* b) { return a->begin_us < b->begin_us; });
    for (const PassTiming* pass : passes) {
      const int64_t begin = to_ns(pass->begin_us), end = to_ns(pass->end_us);
      size_t lane = 0;
      while (lane < lane_end_ns.size() && lane_end_ns[lane] > begin) ++lane;
      if (lane == lane_end_ns.size()) lane_end_ns.push_back(end);
      lane_end_ns[lane] = end;
      events.push_back(complete_event(pass->name, "pass", first_pass_tid + static_cast<int>(lane),
                                      begin, end, {{"frame", frame.frame}, {"ms", pass->ms()}}));
    }

    for (const JobRecord& job : frame.jobs) {
      events.push_back(complete_event(job.name, "job", static_cast<int>(job.worker) + 1,
                                      to_ns(job.begin_us), to_ns(job.end_us),
                                      {{"frame", frame.frame}}));
    }
  }

  nlohmann::json metadata = nlohmann::json::array();
  metadata.push_back({{"name", "process_name"},
                      {"ph", "M"},
                      {"pid", kPid},
                      {"args", {{"name", "cpurender " + report.scene + " (" + report.profile + ")"}}}});
  auto add = [&](const nlohmann::json& entries) {
    for (const auto& entry : entries) metadata.push_back(entry);
  };
  add(thread_metadata(frames_tid, "frames", 0));
  for (size_t lane = 0; lane < std::max<size_t>(1, lane_end_ns.size()); ++lane) {
    add(thread_metadata(first_pass_tid + static_cast<int>(lane),
                        lane == 0 ? "passes" : "passes " + std::to_string(lane + 1),
                        1 + static_cast<int>(lane)));
  }
  const int first_worker_sort = 1 + static_cast<int>(std::max<size_t>(1, lane_end_ns.size()));
  for (uint32_t w = 0; w < workers; ++w) {
    add(thread_metadata(static_cast<int>(w) + 1, w == 0 ? "main" : "worker " + std::to_string(w),
                        first_worker_sort + static_cast<int>(w)));
  }
  for (auto& event : events) metadata.push_back(std::move(event));
  // No "displayTimeUnit": Perfetto reinterprets the timestamps' unit from it.
  return {{"traceEvents", std::move(metadata)}};
}

void write_chrome_trace(const std::string& path, const RunReport& report) {
  write_file_atomic(path, chrome_trace_json(report).dump() + "\n");
}

}  // namespace cr
