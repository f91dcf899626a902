// Frame graph: culling of unread passes, ordering by declared resources.
#include <doctest/doctest.h>

#include <atomic>
#include <mutex>
#include <vector>

#include "engine/render/frame_graph.h"

using cr::FrameGraph;

TEST_CASE("frame graph culls passes whose outputs nobody reads") {
  cr::JobSystem js(2);
  FrameGraph g;
  std::vector<std::string> ran;
  std::mutex m;
  auto pass = [&](const char* name) {
    return [&, name] {
      std::lock_guard<std::mutex> lock(m);
      ran.push_back(name);
    };
  };
  g.add_pass("shadow", [](FrameGraph::Builder& b) { b.write("shadow_map"); }, pass("shadow"));
  g.add_pass("fog", [](FrameGraph::Builder& b) { b.read("shadow_map").write("fog_volume"); }, pass("fog"));
  g.add_pass("geometry", [](FrameGraph::Builder& b) { b.write("visibility"); }, pass("geometry"));
  g.add_pass("shade", [](FrameGraph::Builder& b) { b.read("visibility").read("shadow_map").write("hdr"); },
             pass("shade"));
  g.add_pass("resolve", [](FrameGraph::Builder& b) { b.read("hdr").write("frame"); }, pass("resolve"));
  g.mark_output("frame");
  g.compile();
  CHECK(g.culled_pass_names() == std::vector<std::string>{"fog"});
  g.execute(js);
  CHECK(ran.size() == 4);
  CHECK(ran.back() == "resolve");
  CHECK(g.timings().size() == 4);
}

TEST_CASE("frame graph orders read-modify-write passes by declaration") {
  cr::JobSystem js(4);
  for (int repeat = 0; repeat < 20; ++repeat) {
    FrameGraph g;
    std::vector<int> order;
    std::mutex m;
    auto step = [&](int k) {
      return [&, k] {
        std::lock_guard<std::mutex> lock(m);
        order.push_back(k);
      };
    };
    g.add_pass("a", [](FrameGraph::Builder& b) { b.write("color"); }, step(0));
    g.add_pass("b", [](FrameGraph::Builder& b) { b.read("color").write("color"); }, step(1));
    g.add_pass("c", [](FrameGraph::Builder& b) { b.read("color").write("color"); }, step(2));
    g.add_pass("out", [](FrameGraph::Builder& b) { b.read("color").write("frame"); }, step(3));
    g.mark_output("frame");
    g.execute(js);
    CHECK(order == std::vector<int>{0, 1, 2, 3});
  }
}

TEST_CASE("frame graph keeps side-effect passes and reports pass errors") {
  cr::JobSystem js(2);
  FrameGraph g;
  g.add_pass("write_file", [](FrameGraph::Builder& b) { b.side_effect(); },
             [] { throw std::runtime_error("disk full"); });
  CHECK_THROWS_WITH(g.execute(js), "disk full");
  FrameGraph dup;
  dup.add_pass("x", [](FrameGraph::Builder&) {}, [] {});
  CHECK_THROWS(dup.add_pass("x", [](FrameGraph::Builder&) {}, [] {}));
}
