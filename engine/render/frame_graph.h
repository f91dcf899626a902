#pragma once
// A frame as a graph of passes (after Filament's FrameGraph). Each pass
// declares the named resources it reads and writes; compile() keeps only the
// passes whose writes are (transitively) read by an output, so work nobody
// consumes is never run. Passes execute as jobs of the job system: passes
// without a dependency between them may run concurrently, and inside a pass
// the body uses parallel_for.
#include <functional>
#include <string>
#include <vector>

#include "engine/core/job_system.h"

namespace cr {

struct PassTiming {
  std::string name;
  double begin_us = 0.0;  // job-system clock
  double end_us = 0.0;
  double ms() const { return (end_us - begin_us) * 1e-3; }
};

class FrameGraph {
 public:
  class Builder {
   public:
    Builder& read(const std::string& resource);   // reading a resource nobody writes is allowed (optional input)
    Builder& write(const std::string& resource);
    Builder& side_effect();                        // never culled (writes files, reports)

   private:
    friend class FrameGraph;
    explicit Builder(size_t pass) : pass_(pass) {}
    size_t pass_;
    FrameGraph* graph_ = nullptr;
  };

  // setup declares reads/writes; execute does the work (may call parallel_for).
  void add_pass(const std::string& name, const std::function<void(Builder&)>& setup,
                std::function<void()> execute);
  // Resources consumed outside the graph (the frame image, the report).
  void mark_output(const std::string& resource);
  // Culls unused passes and orders the rest. Throws Error on a write-write
  // conflict with no order between writers or on a cycle.
  void compile();
  // Runs the compiled graph. Rethrows the first error of a pass.
  void execute(JobSystem& jobs);

  std::vector<std::string> executed_pass_names() const;  // in declaration order
  std::vector<std::string> culled_pass_names() const;
  const std::vector<PassTiming>& timings() const { return timings_; }  // declaration order

 private:
  struct Pass {
    std::string name;
    std::vector<std::string> reads;
    std::vector<std::string> writes;
    bool side_effect = false;
    bool alive = false;
    std::function<void()> execute;
    std::vector<size_t> deps;
  };
  std::vector<Pass> passes_;
  std::vector<std::string> outputs_;
  std::vector<PassTiming> timings_;
  bool compiled_ = false;
};

}  // namespace cr
