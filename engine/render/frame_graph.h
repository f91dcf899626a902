#pragma once
// A frame as a graph of passes (after Filament's FrameGraph). Resources are
// typed, versioned handles. import() names an object whose contents exist
// before the frame (a buffer kept across frames, a plugin's LUTs or history):
// it can be read at once. create() names an object this frame fills: reading
// it before a pass writes it is an error of compile(). A pass's write returns
// the resource's next version and leaves the handle it was given stale; a read
// names the version it reads. So a read depends on exactly the pass that wrote
// its version, and a write waits for the writer and the readers of the version
// it replaces: a misspelt or missing input is an error, never a dropped edge.
//
// compile() keeps only the passes whose writes are (transitively) read by an
// output or that have side effects, so work nobody consumes never runs.
// Passes execute as jobs of the job system: passes without a dependency
// between them may run concurrently, and inside a pass the body uses
// parallel_for. A pass's body gets its resources from the graph
// (Resources::get), only those it declared.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <typeinfo>
#include <vector>

#include "engine/core/frame_timing.h"
#include "engine/core/job_system.h"

namespace cr {

// A resource at one version; default-constructed: no resource.
class FrameGraphHandle {
 public:
  FrameGraphHandle() = default;
  bool valid() const { return index_ != kNone; }
  uint32_t index() const { return index_; }
  uint32_t version() const { return version_; }

 protected:
  FrameGraphHandle(uint32_t index, uint32_t version) : index_(index), version_(version) {}
  static constexpr uint32_t kNone = UINT32_MAX;
  uint32_t index_ = kNone;
  uint32_t version_ = 0;
  friend class FrameGraph;
};

// A handle to a resource of type T.
template <class T>
class FrameGraphId : public FrameGraphHandle {
 public:
  FrameGraphId() = default;

 private:
  explicit FrameGraphId(FrameGraphHandle h) : FrameGraphHandle(h) {}
  friend class FrameGraph;
};

class FrameGraph {
 public:
  // Declares a pass's accesses while the pass is added.
  class Builder {
   public:
    template <class T>
    FrameGraphId<T> read(FrameGraphId<T> h) {
      graph_.declare_read(pass_, h);
      return h;
    }
    // A read for ordering only: the pass does not get() it (the plugins'
    // composite inputs, which their composite functions read themselves).
    void read(FrameGraphHandle h) { graph_.declare_read(pass_, h); }
    // Returns the version this pass writes; `h` is stale afterwards.
    template <class T>
    FrameGraphId<T> write(FrameGraphId<T> h) {
      return FrameGraphId<T>(graph_.declare_write(pass_, h));
    }
    Builder& side_effect();  // never culled (writes files, reports)

   private:
    friend class FrameGraph;
    Builder(FrameGraph& graph, size_t pass) : graph_(graph), pass_(pass) {}
    FrameGraph& graph_;
    size_t pass_;
  };

  // What a pass's body sees: the resources it declared, and the job system.
  class Resources {
   public:
    // A resource the pass reads or writes.
    template <class T>
    const T& get(FrameGraphId<T> h) const {
      return *static_cast<const T*>(graph_.object(pass_, h, typeid(T), false));
    }
    // A resource the pass writes.
    template <class T>
    T& get_mutable(FrameGraphId<T> h) const {
      return *static_cast<T*>(graph_.object(pass_, h, typeid(T), true));
    }
    JobSystem& jobs() const { return jobs_; }

   private:
    friend class FrameGraph;
    Resources(const FrameGraph& graph, size_t pass, JobSystem& jobs) : graph_(graph), pass_(pass), jobs_(jobs) {}
    const FrameGraph& graph_;
    size_t pass_;
    JobSystem& jobs_;
  };

  template <class T>
  FrameGraphId<T> import(const std::string& name, T& object) {
    return FrameGraphId<T>(add_resource(name, &object, typeid(T), true));
  }
  template <class T>
  FrameGraphId<T> create(const std::string& name, T& object) {
    return FrameGraphId<T>(add_resource(name, &object, typeid(T), false));
  }

  // setup declares the pass's accesses into its Data (the handles it uses);
  // execute does the work with the same Data.
  template <class Data>
  void add_pass(const std::string& name, const std::function<void(Builder&, Data&)>& setup,
                std::function<void(const Resources&, const Data&)> execute) {
    auto data = std::make_shared<Data>();
    Builder b = begin_pass(name);
    setup(b, *data);
    passes_.back().execute = [data, execute = std::move(execute)](const Resources& r) { execute(r, *data); };
  }
  // A resource consumed outside the graph (the frame image): the pass that
  // wrote this version is kept.
  void mark_output(FrameGraphHandle h);
  // Derives the order, culls unused passes. Throws Error naming the pass and
  // resource for a read of a created resource no pass writes, an access
  // through a stale handle, or an invalid handle.
  void compile();
  // Runs the compiled graph. Rethrows the first error of a pass.
  void execute(JobSystem& jobs);

  std::vector<std::string> executed_pass_names() const;  // in declaration order
  std::vector<std::string> culled_pass_names() const;
  const std::vector<PassTiming>& timings() const { return timings_; }  // declaration order

 private:
  struct Resource {
    std::string name;
    void* object;
    const std::type_info* type;
    bool imported;
    uint32_t version = 0;  // the latest version
  };
  struct Access {
    uint32_t resource;
    uint32_t version;  // read: the version read; write: the version written
  };
  struct Pass {
    std::string name;
    std::vector<Access> reads, writes;
    bool side_effect = false;
    bool alive = false;
    std::function<void(const Resources&)> execute;
    std::vector<size_t> deps;
  };

  FrameGraphHandle add_resource(const std::string& name, void* object, const std::type_info& type, bool imported);
  Builder begin_pass(const std::string& name);
  void declare_read(size_t pass, FrameGraphHandle h);
  FrameGraphHandle declare_write(size_t pass, FrameGraphHandle h);
  bool check_handle(size_t pass, FrameGraphHandle h, const char* access);
  void* object(size_t pass, FrameGraphHandle h, const std::type_info& type, bool write) const;

  std::vector<Resource> resources_;
  std::vector<Pass> passes_;
  std::vector<Access> outputs_;
  std::vector<std::string> errors_;  // reported by compile()
  std::vector<PassTiming> timings_;
  bool compiled_ = false;
};

}  // namespace cr
