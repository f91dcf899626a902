#include "engine/render/frame_graph.h"

#include <algorithm>

#include "engine/core/error.h"

namespace cr {

FrameGraph::Builder& FrameGraph::Builder::read(const std::string& resource) {
  graph_->passes_[pass_].reads.push_back(resource);
  return *this;
}

FrameGraph::Builder& FrameGraph::Builder::write(const std::string& resource) {
  graph_->passes_[pass_].writes.push_back(resource);
  return *this;
}

FrameGraph::Builder& FrameGraph::Builder::side_effect() {
  graph_->passes_[pass_].side_effect = true;
  return *this;
}

void FrameGraph::add_pass(const std::string& name, const std::function<void(Builder&)>& setup,
                          std::function<void()> execute) {
  if (compiled_) throw Error("frame graph: pass '" + name + "' added after compile()");
  for (const Pass& p : passes_)
    if (p.name == name) throw Error("frame graph: duplicate pass name '" + name + "'");
  passes_.push_back(Pass{name, {}, {}, false, false, std::move(execute), {}});
  Builder b(passes_.size() - 1);
  b.graph_ = this;
  setup(b);
}

void FrameGraph::mark_output(const std::string& resource) { outputs_.push_back(resource); }

static bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

void FrameGraph::compile() {
  const size_t n = passes_.size();
  // Passes are ordered by declaration. A read depends on the latest earlier
  // writer of the resource; a write is ordered after earlier writers and
  // readers of the same resource (no reordering hazards).
  std::vector<std::vector<size_t>> data_deps(n);  // deps that carry data (reads)
  for (size_t i = 0; i < n; ++i) {
    Pass& p = passes_[i];
    std::vector<size_t> deps;
    for (const std::string& r : p.reads)
      for (size_t j = i; j-- > 0;)
        if (contains(passes_[j].writes, r)) {
          deps.push_back(j);
          data_deps[i].push_back(j);
          break;
        }
    for (const std::string& w : p.writes)
      for (size_t j = 0; j < i; ++j)
        if (contains(passes_[j].writes, w) || contains(passes_[j].reads, w)) deps.push_back(j);
    std::sort(deps.begin(), deps.end());
    deps.erase(std::unique(deps.begin(), deps.end()), deps.end());
    p.deps = std::move(deps);
  }
  // Liveness: a pass lives if it has side effects, is the last writer of an
  // output, or a live pass reads what it wrote. Walk backwards once: data
  // dependencies always point to earlier passes.
  for (Pass& p : passes_) p.alive = p.side_effect;
  for (const std::string& out : outputs_)
    for (size_t j = n; j-- > 0;)
      if (contains(passes_[j].writes, out)) {
        passes_[j].alive = true;
        break;
      }
  for (size_t i = n; i-- > 0;)
    if (passes_[i].alive)
      for (size_t d : data_deps[i]) passes_[d].alive = true;
  compiled_ = true;
}

void FrameGraph::execute(JobSystem& jobs) {
  if (!compiled_) compile();
  JobSystem::Graph graph;
  std::vector<size_t> job_of(passes_.size(), SIZE_MAX);
  std::vector<size_t> alive;
  for (size_t i = 0; i < passes_.size(); ++i)
    if (passes_[i].alive) alive.push_back(i);
  timings_.assign(alive.size(), PassTiming{});
  for (size_t k = 0; k < alive.size(); ++k) {
    const size_t i = alive[k];
    std::vector<JobSystem::Graph::Id> deps;
    for (size_t d : passes_[i].deps)
      if (job_of[d] != SIZE_MAX) deps.push_back(job_of[d]);
    PassTiming* timing = &timings_[k];
    timing->name = passes_[i].name;
    job_of[i] = graph.add("pass:" + passes_[i].name,
                          [this, i, timing, &jobs] {
                            timing->begin_us = jobs.now_us();
                            passes_[i].execute();
                            timing->end_us = jobs.now_us();
                          },
                          std::move(deps));
  }
  jobs.run(graph);
}

std::vector<std::string> FrameGraph::executed_pass_names() const {
  std::vector<std::string> v;
  for (const Pass& p : passes_)
    if (p.alive) v.push_back(p.name);
  return v;
}

std::vector<std::string> FrameGraph::culled_pass_names() const {
  std::vector<std::string> v;
  for (const Pass& p : passes_)
    if (!p.alive) v.push_back(p.name);
  return v;
}

}  // namespace cr
