#include "engine/core/job_system.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <memory>

#include "engine/core/error.h"

namespace cr {

namespace {
thread_local uint32_t tls_worker = 0;

// Completion state shared by the tasks of one parallel_for or graph run.
struct Batch {
  std::atomic<size_t> remaining{0};
  std::mutex error_mutex;
  size_t error_index = SIZE_MAX;
  std::exception_ptr error;

  void fail(size_t index, std::exception_ptr e) {
    std::lock_guard<std::mutex> lock(error_mutex);
    if (index < error_index) {  // keep the lowest index: deterministic error
      error_index = index;
      error = std::move(e);
    }
  }
};
}  // namespace

JobSystem::JobSystem(unsigned threads)
    : thread_count_(std::max(1u, threads)), epoch_(Clock::now()) {
  for (uint32_t i = 1; i < thread_count_; ++i) workers_.emplace_back([this, i] { worker_loop(i); });
}

JobSystem::~JobSystem() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  work_cv_.notify_all();
  for (auto& t : workers_) t.join();
}

unsigned JobSystem::default_thread_count() {
  unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : n;
}

uint32_t JobSystem::current_worker() { return tls_worker; }

double JobSystem::now_us() const {
  return std::chrono::duration<double, std::micro>(Clock::now() - epoch_).count();
}

void JobSystem::record(const std::string& name, double begin, double end) {
  std::lock_guard<std::mutex> lock(records_mutex_);
  records_.push_back({name, tls_worker, begin, end});
}

std::vector<JobRecord> JobSystem::take_records() {
  std::vector<JobRecord> out;
  {
    std::lock_guard<std::mutex> lock(records_mutex_);
    out.swap(records_);
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const JobRecord& a, const JobRecord& b) { return a.begin_us < b.begin_us; });
  return out;
}

void JobSystem::push(std::vector<Task> tasks) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto& t : tasks) queue_.push_back(std::move(t));
  }
  work_cv_.notify_all();
}

bool JobSystem::try_run_one(const void* batch) {
  Task task;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = queue_.begin();
    if (batch)
      while (it != queue_.end() && it->batch != batch) ++it;
    if (it == queue_.end()) return false;
    task = std::move(*it);
    queue_.erase(it);
  }
  task.fn();
  return true;
}

void JobSystem::worker_loop(uint32_t index) {
  tls_worker = index;
  for (;;) {
    Task task;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      work_cv_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping and drained
      task = std::move(queue_.front());
      queue_.pop_front();
    }
    task.fn();
  }
}

// Runs queued work until `remaining` reaches zero. Helping (instead of just
// sleeping) is what makes nested parallel_for calls deadlock-free: the
// waiter can always run its own loop's remaining chunks itself.
static void wait_helping(std::atomic<size_t>& remaining, std::mutex& m, std::condition_variable& cv,
                         const std::function<bool()>& run_one) {
  while (remaining.load(std::memory_order_acquire) != 0) {
    if (run_one()) continue;
    std::unique_lock<std::mutex> lock(m);
    cv.wait_for(lock, std::chrono::microseconds(200),
                [&] { return remaining.load(std::memory_order_acquire) == 0; });
  }
}

void JobSystem::parallel_for(const std::string& name, size_t count, size_t grain,
                             const std::function<void(size_t, size_t)>& body) {
  if (count == 0) return;
  grain = std::max<size_t>(1, grain);
  const size_t chunks = (count + grain - 1) / grain;
  // The batch lives on this stack: the caller returns only when every chunk
  // has counted down, and a chunk touches the batch only before that.
  Batch batch;
  batch.remaining.store(chunks);

  auto run_chunk = [this, &batch, &body, &name, count, grain](size_t c) {
    const size_t b = c * grain, e = std::min(count, b + grain);
    const double t0 = now_us();
    try {
      body(b, e);
    } catch (...) {
      batch.fail(c, std::current_exception());
    }
    record(name, t0, now_us());
    if (batch.remaining.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      std::lock_guard<std::mutex> lock(mutex_);
      done_cv_.notify_all();
    }
  };

  if (thread_count_ == 1 || chunks == 1) {
    for (size_t c = 0; c < chunks; ++c) run_chunk(c);
  } else {
    std::vector<Task> tasks;
    tasks.reserve(chunks - 1);
    for (size_t c = 1; c < chunks; ++c) tasks.push_back({[run_chunk, c] { run_chunk(c); }, &batch});
    push(std::move(tasks));
    run_chunk(0);
    wait_helping(batch.remaining, mutex_, done_cv_, [this, &batch] { return try_run_one(&batch); });
  }
  if (batch.error) std::rethrow_exception(batch.error);
}

JobSystem::Graph::Id JobSystem::Graph::add(std::string name, std::function<void()> fn,
                                           std::vector<Id> deps) {
  const Id id = nodes_.size();
  for (Id d : deps)
    if (d >= id) throw Error("job graph: job '" + name + "' depends on a job added after it");
  nodes_.push_back({std::move(name), std::move(fn), std::move(deps)});
  return id;
}

// The state of one run(): on the caller's stack, which outlives every job
// (a job touches it only before its final count-down).
struct JobSystem::GraphRun {
  const Graph& graph;
  std::vector<std::vector<size_t>> dependents;
  std::unique_ptr<std::atomic<size_t>[]> pending;
  std::unique_ptr<std::atomic<bool>[]> skipped;  // a dependency failed
  Batch batch;
};

void JobSystem::run_graph_node(GraphRun* run, size_t i) {
  const auto& node = run->graph.nodes_[i];
  if (!run->skipped[i].load()) {
    const double t0 = now_us();
    try {
      node.fn();
    } catch (...) {
      run->batch.fail(i, std::current_exception());
      for (size_t d : run->dependents[i]) run->skipped[d].store(true);
    }
    record(node.name, t0, now_us());
  } else {
    for (size_t d : run->dependents[i]) run->skipped[d].store(true);
  }
  std::vector<Task> ready;
  for (size_t d : run->dependents[i])
    if (run->pending[d].fetch_sub(1, std::memory_order_acq_rel) == 1)
      ready.push_back({[this, run, d] { run_graph_node(run, d); }, nullptr});
  if (!ready.empty()) push(std::move(ready));
  if (run->batch.remaining.fetch_sub(1, std::memory_order_acq_rel) == 1) {
    std::lock_guard<std::mutex> lock(mutex_);
    done_cv_.notify_all();
  }
}

void JobSystem::run(const Graph& graph) {
  const size_t n = graph.nodes_.size();
  if (n == 0) return;
  // Dependencies always point backwards (checked in add), so the graph is
  // acyclic. A job whose dependency failed is skipped (but still counts down)
  // so the run always terminates; the first error is rethrown.
  GraphRun run{graph, std::vector<std::vector<size_t>>(n), std::make_unique<std::atomic<size_t>[]>(n),
               std::make_unique<std::atomic<bool>[]>(n), {}};
  for (size_t i = 0; i < n; ++i) {
    run.pending[i].store(graph.nodes_[i].deps.size());
    run.skipped[i].store(false);
    for (size_t d : graph.nodes_[i].deps) run.dependents[d].push_back(i);
  }
  run.batch.remaining.store(n);
  std::vector<Task> roots;
  for (size_t i = 0; i < n; ++i)
    if (graph.nodes_[i].deps.empty()) roots.push_back({[this, r = &run, i] { run_graph_node(r, i); }, nullptr});
  push(std::move(roots));
  wait_helping(run.batch.remaining, mutex_, done_cv_, [this] { return try_run_one(nullptr); });
  if (run.batch.error) std::rethrow_exception(run.batch.error);
}

}  // namespace cr
