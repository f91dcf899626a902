#include "engine/cli/golden_render.h"

#include <cstring>
#include <sstream>

#include "engine/cli/cli_common.h"
#include "engine/render/renderer.h"

namespace cr {

namespace {

// Bitwise, not ==: -0 vs +0 and differing NaN payloads are differences too.
bool same_bits(const void* a, const void* b, size_t bytes) { return std::memcmp(a, b, bytes) == 0; }

// Counts the pixels of a buffer whose `stride` bytes differ; reports the first.
void compare_buffer(const char* name, const uint8_t* a, const uint8_t* b, size_t pixels, size_t stride, int width,
                    std::ostringstream& out) {
  size_t differing = 0, first = 0;
  for (size_t i = 0; i < pixels; ++i)
    if (!same_bits(a + i * stride, b + i * stride, stride) && differing++ == 0) first = i;
  if (differing == 0) return;
  if (out.tellp() > 0) out << "; ";
  out << name << " differs in " << differing << " pixel" << (differing == 1 ? "" : "s") << ", first at ("
      << first % size_t(width) << ", " << first / size_t(width) << ")";
}

}  // namespace

std::string describe_buffer_difference(const FrameBuffers& a, const FrameBuffers& b) {
  if (a.width != b.width || a.height != b.height) return "frame sizes differ";
  const size_t n = size_t(a.width) * size_t(a.height);
  std::ostringstream out;
  compare_buffer("colour", reinterpret_cast<const uint8_t*>(a.color.data()),
                 reinterpret_cast<const uint8_t*>(b.color.data()), n, sizeof(glm::vec3), a.width, out);
  compare_buffer("depth", reinterpret_cast<const uint8_t*>(a.depth.data()),
                 reinterpret_cast<const uint8_t*>(b.depth.data()), n, sizeof(float), a.width, out);
  compare_buffer("distance", reinterpret_cast<const uint8_t*>(a.distance.data()),
                 reinterpret_cast<const uint8_t*>(b.distance.data()), n, sizeof(float), a.width, out);
  compare_buffer("display", a.display.data(), b.display.data(), n, 3, a.width, out);
  return out.str();
}

GoldenRender render_golden_case(const GoldenCase& c, const PluginRegistry& registry, int width, int height,
                                unsigned threads) {
  const RunSetup setup = load_run(c.scene_path, c.profile_path, registry, width, height, 1);
  JobSystem jobs_one(1), jobs_many(threads);
  Renderer one(*setup.scene, setup.description, setup.profile, registry.create_all(), jobs_one);
  Renderer many(*setup.scene, setup.description, setup.profile, registry.create_all(), jobs_many);
  attach_playback(one, setup);  // both pose the shared scene at the same frame's time
  attach_playback(many, setup);

  GoldenRender r;
  r.threads = threads;
  size_t next_kept = 0;
  // Lockstep: both renderers see the same frame sequence, so temporal state
  // (history, LUT schedules) is compared frame by frame, not just at the end.
  for (int f = 0; f <= c.last_frame; ++f) {
    r.ms_one_thread += one.render_frame(f).frame_ms;
    r.ms_threads += many.render_frame(f).frame_ms;
    if (r.deterministic) {
      const std::string difference = describe_buffer_difference(one.buffers(), many.buffers());
      if (!difference.empty()) {
        r.deterministic = false;
        r.determinism_detail = "frame " + std::to_string(f) + ", 1 vs " + std::to_string(threads) +
                               " threads: " + difference;
      }
    }
    if (next_kept < c.kept_frames.size() && c.kept_frames[next_kept] == f) {
      const FrameBuffers& b = many.buffers();
      r.kept.push_back({f, Image8{b.width, b.height, 3, b.display}});
      ++next_kept;
    }
  }
  return r;
}

}  // namespace cr
