#include "engine/render/frame_graph.h"

#include <algorithm>

#include "engine/core/error.h"

namespace cr {

FrameGraphHandle FrameGraph::add_resource(const std::string& name, void* object, const std::type_info& type,
                                          bool imported) {
  if (compiled_) throw Error("frame graph: resource '" + name + "' added after compile()");
  resources_.push_back(Resource{name, object, &type, imported, 0});
  return FrameGraphHandle(uint32_t(resources_.size() - 1), 0);
}

FrameGraph::Builder FrameGraph::begin_pass(const std::string& name) {
  if (compiled_) throw Error("frame graph: pass '" + name + "' added after compile()");
  for (const Pass& p : passes_)
    if (p.name == name) throw Error("frame graph: duplicate pass name '" + name + "'");
  passes_.push_back(Pass{name, {}, {}, false, false, {}, {}});
  return Builder(*this, passes_.size() - 1);
}

FrameGraph::Builder& FrameGraph::Builder::side_effect() {
  graph_.passes_[pass_].side_effect = true;
  return *this;
}

bool FrameGraph::check_handle(size_t pass, FrameGraphHandle h, const char* access) {
  const std::string& who = passes_[pass].name;
  if (!h.valid() || h.index() >= resources_.size()) {
    errors_.push_back("pass '" + who + "' " + access + " an invalid resource handle");
    return false;
  }
  const Resource& r = resources_[h.index()];
  if (h.version() != r.version) {
    // The object holds the newest version only: an older one is gone.
    errors_.push_back("pass '" + who + "' " + access + " version " + std::to_string(h.version()) + " of '" + r.name +
                      "', but a pass declared before it wrote version " + std::to_string(r.version) +
                      " (a stale handle)");
    return false;
  }
  return true;
}

void FrameGraph::declare_read(size_t pass, FrameGraphHandle h) {
  if (!check_handle(pass, h, "reads")) return;
  const Resource& r = resources_[h.index()];
  if (h.version() == 0 && !r.imported)
    errors_.push_back("pass '" + passes_[pass].name + "' reads '" + r.name + "', which no pass writes before it");
  passes_[pass].reads.push_back({h.index(), h.version()});
}

FrameGraphHandle FrameGraph::declare_write(size_t pass, FrameGraphHandle h) {
  if (!check_handle(pass, h, "writes")) return FrameGraphHandle();
  Resource& r = resources_[h.index()];
  ++r.version;
  passes_[pass].writes.push_back({h.index(), r.version});
  return FrameGraphHandle(h.index(), r.version);
}

void FrameGraph::mark_output(FrameGraphHandle h) {
  if (!h.valid() || h.index() >= resources_.size()) {
    errors_.push_back("an output is an invalid resource handle");
    return;
  }
  outputs_.push_back({h.index(), h.version()});
}

void* FrameGraph::object(size_t pass, FrameGraphHandle h, const std::type_info& type, bool write) const {
  const Pass& p = passes_[pass];
  auto declared = [&](const std::vector<Access>& list) {
    return std::any_of(list.begin(), list.end(), [&](const Access& a) { return a.resource == h.index(); });
  };
  if (!h.valid() || h.index() >= resources_.size() || *resources_[h.index()].type != type)
    throw Error("frame graph: pass '" + p.name + "' asks for an invalid resource handle");
  if (!declared(p.writes) && (write || !declared(p.reads)))
    throw Error("frame graph: pass '" + p.name + "' uses '" + resources_[h.index()].name + "' without declaring " +
                (write ? "a write" : "a read"));
  return resources_[h.index()].object;
}

void FrameGraph::compile() {
  if (!errors_.empty()) throw Error("frame graph: " + errors_.front());
  const size_t n = passes_.size();
  // Who wrote each version, and who read it.
  auto key = [](const Access& a) { return (uint64_t(a.resource) << 32) | a.version; };
  std::vector<std::pair<uint64_t, size_t>> writer, readers;
  for (size_t i = 0; i < n; ++i) {
    for (const Access& a : passes_[i].writes) writer.emplace_back(key(a), i);
    for (const Access& a : passes_[i].reads) readers.emplace_back(key(a), i);
  }
  std::sort(writer.begin(), writer.end());
  std::sort(readers.begin(), readers.end());
  auto writer_of = [&](uint64_t k) -> size_t {
    auto it = std::lower_bound(writer.begin(), writer.end(), std::make_pair(k, size_t(0)));
    return it != writer.end() && it->first == k ? it->second : SIZE_MAX;
  };
  // A read depends on the writer of its version (data); a write of version v
  // on the writer and the readers of version v - 1 (ordering only).
  std::vector<std::vector<size_t>> data_deps(n);
  for (size_t i = 0; i < n; ++i) {
    Pass& p = passes_[i];
    std::vector<size_t> deps;
    for (const Access& a : p.reads) {
      const size_t w = writer_of(key(a));
      if (w == SIZE_MAX || w == i) continue;
      deps.push_back(w);
      data_deps[i].push_back(w);
    }
    for (const Access& a : p.writes) {
      const uint64_t before = key({a.resource, a.version - 1});
      const size_t w = writer_of(before);
      if (w != SIZE_MAX && w != i) deps.push_back(w);
      for (auto it = std::lower_bound(readers.begin(), readers.end(), std::make_pair(before, size_t(0)));
           it != readers.end() && it->first == before; ++it)
        if (it->second != i) deps.push_back(it->second);
    }
    std::sort(deps.begin(), deps.end());
    deps.erase(std::unique(deps.begin(), deps.end()), deps.end());
    p.deps = std::move(deps);
  }
  // Liveness: a pass lives if it has side effects, wrote an output, or a
  // live pass reads what it wrote. Walk backwards once: dependencies always
  // point to passes declared earlier.
  for (Pass& p : passes_) p.alive = p.side_effect;
  for (const Access& out : outputs_) {
    const size_t w = writer_of(key(out));
    if (w != SIZE_MAX) passes_[w].alive = true;
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
                            passes_[i].execute(Resources(*this, i, jobs));
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
