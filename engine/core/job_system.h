#pragma once
// A fixed pool of worker threads running a job graph and parallel-for loops.
//
// Determinism contract: the job system never decides *what* a job computes,
// only *when*. Callers partition output so every element is written by exactly
// one job, and any reduction is done afterwards in index order.
//
// Waiting threads help: a thread blocked in parallel_for() executes the
// queued chunks of that same loop (so jobs may call parallel_for without
// deadlock, and a pass's wall time never includes another pass's jobs); a
// thread blocked in run() executes any queued job.
// An exception thrown by a job is captured and rethrown to the caller (the one
// from the lowest job/chunk index, so the reported error is deterministic).
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace cr {

using Clock = std::chrono::steady_clock;

// One executed job: what it was, which worker ran it, and when.
struct JobRecord {
  std::string name;       // job name (pass or loop name)
  uint32_t worker = 0;    // 0 = calling (main) thread, 1..N-1 = pool workers
  double begin_us = 0.0;  // microseconds since the job system's epoch
  double end_us = 0.0;
};

class JobSystem {
 public:
  // threads = total threads doing work, including the caller (>= 1).
  explicit JobSystem(unsigned threads);
  ~JobSystem();
  JobSystem(const JobSystem&) = delete;
  JobSystem& operator=(const JobSystem&) = delete;

  unsigned thread_count() const { return thread_count_; }

  // Runs body(begin, end) over [0, count) in chunks of `grain` elements.
  // Chunk boundaries depend only on count and grain, never on thread count.
  void parallel_for(const std::string& name, size_t count, size_t grain,
                    const std::function<void(size_t begin, size_t end)>& body);

  // A graph of named jobs with dependencies; run() executes it to completion.
  class Graph {
   public:
    using Id = size_t;
    Id add(std::string name, std::function<void()> fn, std::vector<Id> deps = {});
    size_t size() const { return nodes_.size(); }

   private:
    friend class JobSystem;
    struct Node {
      std::string name;
      std::function<void()> fn;
      std::vector<Id> deps;
    };
    std::vector<Node> nodes_;
  };
  void run(const Graph& graph);

  // Job records since the last take_records(), in completion order per worker
  // merged by begin time (a report artefact; not used for any computation).
  std::vector<JobRecord> take_records();
  double now_us() const;
  static unsigned default_thread_count();
  // Worker index of the calling thread (0 for threads outside the pool).
  static uint32_t current_worker();

 private:
  struct Task {
    std::function<void()> fn;
    const void* batch = nullptr;  // the parallel_for the task belongs to (null: a graph job)
  };
  struct GraphRun;
  void run_graph_node(GraphRun* run, size_t index);
  void worker_loop(uint32_t index);
  // Runs one queued task; when `batch` is set, only a task of that batch.
  bool try_run_one(const void* batch);
  void push(std::vector<Task> tasks);
  void record(const std::string& name, double begin, double end);

  unsigned thread_count_;
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable work_cv_;
  std::condition_variable done_cv_;
  std::deque<Task> queue_;
  bool stopping_ = false;
  Clock::time_point epoch_;
  std::mutex records_mutex_;
  std::vector<JobRecord> records_;
};

}  // namespace cr
