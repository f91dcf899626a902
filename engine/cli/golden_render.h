#pragma once
// Renders one golden case twice, with 1 thread and with many, frame by frame
// in lockstep, and checks that every buffer of every frame is bit-identical
// (the determinism rule of DESIGN.md). Results stay in memory: the golden
// command writes nothing until every case has rendered.
#include <string>
#include <vector>

#include "engine/cli/golden_cases.h"
#include "engine/output/image.h"
#include "engine/render/plugin_registry.h"

namespace cr {

struct GoldenFrame {
  int frame = 0;
  Image8 image;  // the resolved sRGB RGB8 frame (what a PNG golden stores)
};

struct GoldenRender {
  std::vector<GoldenFrame> kept;  // the case's kept frames, in order
  unsigned threads = 0;           // the multi-thread run's thread count
  double ms_one_thread = 0.0;     // summed frame times of frames 0..last
  double ms_threads = 0.0;
  bool deterministic = true;
  std::string determinism_detail;  // the first difference, when not deterministic
};

// The first difference between two frames' buffers (colour, depth, distance,
// display) as text, compared bit for bit; empty when identical.
std::string describe_buffer_difference(const FrameBuffers& one_thread, const FrameBuffers& threads);

// Loads the case's scene and profile at width x height and renders frames
// 0..last_frame with 1 and with `threads` threads. Throws what loading or
// rendering throws.
GoldenRender render_golden_case(const GoldenCase& c, const PluginRegistry& registry, int width, int height,
                                unsigned threads);

}  // namespace cr
