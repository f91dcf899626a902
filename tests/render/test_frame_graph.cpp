// Frame graph: typed, versioned resources; culling of unread passes; ordering
// by versions; errors for unwritten reads, stale handles and undeclared use.
#include <doctest/doctest.h>

#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/core/error.h"
#include "engine/render/frame_graph.h"

using cr::FrameGraph;
using cr::FrameGraphId;
using Builder = FrameGraph::Builder;
using Resources = FrameGraph::Resources;

namespace {

struct None {};

// The names of the passes that ran, in the order they ran.
struct RunLog {
  std::mutex m;
  std::vector<std::string> ran;
  void add(const std::string& name) {
    std::lock_guard<std::mutex> lock(m);
    ran.push_back(name);
  }
};

}  // namespace

TEST_CASE("frame graph culls passes whose outputs nobody reads") {
  cr::JobSystem js(2);
  FrameGraph g;
  RunLog log;
  int shadow_map = 0, fog_volume = 0, visibility = 0, hdr = 0, frame = 0;
  auto shadow = g.create("shadow_map", shadow_map);
  auto fog = g.create("fog_volume", fog_volume);
  auto vis = g.create("visibility", visibility);
  auto color = g.create("hdr", hdr);
  auto image = g.create("frame", frame);
  auto pass = [&](const char* name) { return [&log, name](const Resources&, const None&) { log.add(name); }; };
  g.add_pass<None>("shadow", [&](Builder& b, None&) { shadow = b.write(shadow); }, pass("shadow"));
  g.add_pass<None>("fog", [&](Builder& b, None&) { b.read(shadow); fog = b.write(fog); }, pass("fog"));
  g.add_pass<None>("geometry", [&](Builder& b, None&) { vis = b.write(vis); }, pass("geometry"));
  g.add_pass<None>("shade", [&](Builder& b, None&) {
    b.read(vis);
    b.read(shadow);
    color = b.write(color);
  }, pass("shade"));
  g.add_pass<None>("resolve", [&](Builder& b, None&) { b.read(color); image = b.write(image); }, pass("resolve"));
  g.mark_output(image);
  g.compile();
  CHECK(g.culled_pass_names() == std::vector<std::string>{"fog"});
  g.execute(js);
  CHECK(log.ran.size() == 4);
  CHECK(log.ran.back() == "resolve");
  CHECK(g.timings().size() == 4);
}

TEST_CASE("frame graph orders read-modify-write passes by version and hands each pass its data") {
  cr::JobSystem js(4);
  for (int repeat = 0; repeat < 20; ++repeat) {
    FrameGraph g;
    std::vector<int> colour_steps;  // the resource's object
    int frame_value = 0;
    auto color = g.create("color", colour_steps);
    auto frame = g.create("frame", frame_value);
    struct Step {
      FrameGraphId<std::vector<int>> color;
    };
    for (int k = 0; k < 3; ++k)
      g.add_pass<Step>("step" + std::to_string(k), [&](Builder& b, Step& d) {
        if (k > 0) b.read(color);
        d.color = color = b.write(color);
      }, [k](const Resources& r, const Step& d) { r.get_mutable(d.color).push_back(k); });
    struct Out {
      FrameGraphId<std::vector<int>> color;
      FrameGraphId<int> frame;
    };
    g.add_pass<Out>("out", [&](Builder& b, Out& d) {
      d.color = b.read(color);
      d.frame = frame = b.write(frame);
    }, [](const Resources& r, const Out& d) { r.get_mutable(d.frame) = int(r.get(d.color).size()); });
    g.mark_output(frame);
    g.execute(js);
    CHECK(colour_steps == std::vector<int>{0, 1, 2});
    CHECK(frame_value == 3);
  }
}

TEST_CASE("frame graph: an imported resource is readable without a writer, a created one is not") {
  cr::JobSystem js(1);
  int lut = 7, sky = 0;
  {
    FrameGraph g;
    auto l = g.import("lut", lut);
    auto s = g.create("sky", sky);
    struct Data {
      FrameGraphId<int> lut, sky;
    };
    g.add_pass<Data>("sky", [&](Builder& b, Data& d) {
      d.lut = b.read(l);
      d.sky = s = b.write(s);
    }, [](const Resources& r, const Data& d) { r.get_mutable(d.sky) = r.get(d.lut) * 2; });
    g.mark_output(s);
    g.execute(js);
    CHECK(sky == 14);
  }
  // A misspelt or missing producer: the read names a resource no pass wrote.
  FrameGraph g;
  auto l = g.create("lut", lut);
  auto s = g.create("sky", sky);
  g.add_pass<None>("sky", [&](Builder& b, None&) {
    b.read(l);
    s = b.write(s);
  }, [](const Resources&, const None&) {});
  g.mark_output(s);
  CHECK_THROWS_WITH_AS(g.compile(), "frame graph: pass 'sky' reads 'lut', which no pass writes before it", cr::Error);
}

TEST_CASE("frame graph: a stale or invalid handle is an error of compile()") {
  int value = 0;
  {
    FrameGraph g;
    auto v = g.create("value", value);
    const auto first = v;
    g.add_pass<None>("a", [&](Builder& b, None&) { v = b.write(v); }, [](const Resources&, const None&) {});
    // Writing through the handle from before "a" wrote: two unordered writers.
    g.add_pass<None>("b", [&](Builder& b, None&) { b.write(first); }, [](const Resources&, const None&) {});
    CHECK_THROWS_WITH_AS(g.compile(), doctest::Contains("pass 'b' writes version 0 of 'value'"), cr::Error);
  }
  {
    FrameGraph g;
    auto v = g.create("value", value);
    g.add_pass<None>("a", [&](Builder& b, None&) { v = b.write(v); }, [](const Resources&, const None&) {});
    const auto written = v;
    g.add_pass<None>("b", [&](Builder& b, None&) { v = b.write(v); }, [](const Resources&, const None&) {});
    // Reading version 1 after "b" replaced it: the object no longer holds it.
    g.add_pass<None>("c", [&](Builder& b, None&) { b.read(written); }, [](const Resources&, const None&) {});
    CHECK_THROWS_WITH_AS(g.compile(), doctest::Contains("pass 'c' reads version 1 of 'value'"), cr::Error);
  }
  FrameGraph g;
  g.add_pass<None>("a", [&](Builder& b, None&) { b.read(FrameGraphId<int>()); }, [](const Resources&, const None&) {});
  CHECK_THROWS_WITH_AS(g.compile(), "frame graph: pass 'a' reads an invalid resource handle", cr::Error);
}

TEST_CASE("frame graph: a pass gets only what it declared, and writes only what it declared writing") {
  cr::JobSystem js(1);
  int a = 1, b_value = 2;
  FrameGraph g;
  auto ha = g.import("a", a);
  auto hb = g.import("b", b_value);
  struct Data {
    FrameGraphId<int> a, b;
  };
  g.add_pass<Data>("reads a", [&](Builder& b, Data& d) {
    d.a = b.read(ha);
    d.b = hb;  // not declared
    b.side_effect();
  }, [](const Resources& r, const Data& d) {
    CHECK(r.get(d.a) == 1);
    CHECK_THROWS_WITH_AS(r.get(d.b), "frame graph: pass 'reads a' uses 'b' without declaring a read", cr::Error);
    CHECK_THROWS_WITH_AS(r.get_mutable(d.a), "frame graph: pass 'reads a' uses 'a' without declaring a write",
                         cr::Error);
  });
  g.execute(js);
}

TEST_CASE("frame graph keeps side-effect passes and reports pass errors") {
  cr::JobSystem js(2);
  FrameGraph g;
  g.add_pass<None>("write_file", [](Builder& b, None&) { b.side_effect(); },
                   [](const Resources&, const None&) { throw std::runtime_error("disk full"); });
  CHECK_THROWS_WITH(g.execute(js), "disk full");
  FrameGraph dup;
  dup.add_pass<None>("x", [](Builder&, None&) {}, [](const Resources&, const None&) {});
  CHECK_THROWS(dup.add_pass<None>("x", [](Builder&, None&) {}, [](const Resources&, const None&) {}));
}
