// Job system: coverage, determinism of partitioning, dependencies, errors,
// nested parallelism. These tests also run under ThreadSanitizer.
#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "engine/core/job_system.h"

using cr::JobSystem;

TEST_CASE("threading: parallel_for writes every element exactly once") {
  for (unsigned threads : {1u, 2u, 3u, 8u}) {
    JobSystem js(threads);
    std::vector<int> hits(10007, 0);
    js.parallel_for("fill", hits.size(), 64, [&](size_t b, size_t e) {
      for (size_t i = b; i < e; ++i) hits[i] += 1;
    });
    CHECK(std::all_of(hits.begin(), hits.end(), [](int h) { return h == 1; }));
  }
}

TEST_CASE("threading: chunking is independent of the thread count") {
  auto chunks = [](unsigned threads) {
    JobSystem js(threads);
    std::vector<std::pair<size_t, size_t>> out(100, {0, 0});
    js.parallel_for("chunks", 1000, 37, [&](size_t b, size_t e) { out[b / 37] = {b, e}; });
    return out;
  };
  const auto one = chunks(1);
  CHECK(one == chunks(2));
  CHECK(one == chunks(8));
  CHECK(one[27] == std::pair<size_t, size_t>{999, 1000});
}

TEST_CASE("threading: a job graph respects dependencies") {
  for (unsigned threads : {1u, 2u, 4u}) {
    JobSystem js(threads);
    std::atomic<int> clock{0};
    std::vector<int> stamp(6, -1);
    JobSystem::Graph g;
    auto job = [&](int i) { return [&, i] { stamp[i] = clock.fetch_add(1); }; };
    auto a = g.add("a", job(0));
    auto b = g.add("b", job(1), {a});
    auto c = g.add("c", job(2), {a});
    auto d = g.add("d", job(3), {b, c});
    g.add("e", job(4));
    g.add("f", job(5), {d});
    js.run(g);
    CHECK(stamp[0] < stamp[1]);
    CHECK(stamp[0] < stamp[2]);
    CHECK(stamp[1] < stamp[3]);
    CHECK(stamp[2] < stamp[3]);
    CHECK(stamp[3] < stamp[5]);
    CHECK(stamp[4] >= 0);
  }
}

TEST_CASE("threading: nested parallel_for inside graph jobs does not deadlock") {
  JobSystem js(3);
  std::vector<long> sums(4, 0);
  JobSystem::Graph g;
  for (int k = 0; k < 4; ++k)
    g.add("outer", [&, k] {
      std::vector<long> part(100, 0);
      js.parallel_for("inner", 100, 7, [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) part[i] = long(i) * (k + 1);
      });
      sums[k] = std::accumulate(part.begin(), part.end(), 0L);  // fixed-order reduction
    });
  js.run(g);
  for (int k = 0; k < 4; ++k) CHECK(sums[k] == 4950L * (k + 1));
}

TEST_CASE("threading: an exception in a job reaches the caller, deterministically") {
  for (unsigned threads : {1u, 2u, 8u}) {
    JobSystem js(threads);
    try {
      js.parallel_for("throws", 1000, 10, [&](size_t b, size_t) {
        if (b == 500 || b == 700) throw std::runtime_error("chunk " + std::to_string(b));
      });
      FAIL("no exception");
    } catch (const std::runtime_error& e) {
      CHECK(std::string(e.what()) == "chunk 500");  // lowest failing chunk wins
    }
    // The pool is still usable afterwards.
    std::atomic<int> n{0};
    js.parallel_for("after", 100, 1, [&](size_t, size_t) { n++; });
    CHECK(n == 100);
  }
}

TEST_CASE("threading: a failing graph job skips its dependents and reports") {
  JobSystem js(2);
  bool dependent_ran = false, independent_ran = false;
  JobSystem::Graph g;
  auto a = g.add("fails", [] { throw std::logic_error("boom"); });
  g.add("dependent", [&] { dependent_ran = true; }, {a});
  g.add("independent", [&] { independent_ran = true; });
  CHECK_THROWS_WITH_AS(js.run(g), "boom", std::logic_error);
  CHECK_FALSE(dependent_ran);
  CHECK(independent_ran);
}

TEST_CASE("threading: every job is recorded with its worker and times") {
  JobSystem js(2);
  js.take_records();
  js.parallel_for("timed", 8, 1, [](size_t, size_t) {});
  const auto records = js.take_records();
  CHECK(records.size() == 8);
  for (const auto& r : records) {
    CHECK(r.name == "timed");
    CHECK(r.worker < 2);
    CHECK(r.end_us >= r.begin_us);
  }
  CHECK(js.take_records().empty());
}

TEST_CASE("job graph rejects forward dependencies") {
  JobSystem::Graph g;
  CHECK_THROWS(g.add("x", [] {}, {3}));
}
