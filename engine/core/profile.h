#pragma once
// A render profile (profiles/*.json): data that selects resolutions, sizes,
// budgets and kernels. Desktop and mobile differ only by these values.
//
// The engine validates its own keys; every other top-level key must be the
// name of a registered plugin section (e.g. "atmosphere", "fog"), which that
// plugin validates. Unknown keys anywhere are an error naming file and key.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/depth_format.h"

namespace cr {

struct Profile {
  std::string name;
  std::string path;
  int width = 1280;
  int height = 720;
  int tile_size = 64;             // screen tile edge in pixels (power of two, 8..256)
  int shadow_map_size = 2048;     // 0 disables the shadow pass
  float shadow_distance = 300.0f; // metres from the camera covered by the shadow map
  int shadow_pcf_radius = 1;      // PCF kernel (2r+1)^2 taps
  float frame_budget_ms = 33.3f;
  // Memory for the decoded textures: each image's RGBA8 mip chain. Where the
  // chains exceed it, the largest drop their top levels until they fit
  // (GltfLoadOptions::texture_decode_budget), with a warning naming each.
  int texture_decode_budget_mb = 512;
  // Dynamic resolution: the scene renders at render_width() x render_height()
  // and is upscaled to width x height before the display transform
  // (engine/render/upscale.h). In [0.25, 1]; 1 renders at the output size.
  float render_scale = 1.0f;
  // Anti-aliasing ("antialiasing": "none" | "msaa2" | "msaa4" | "msaa8"):
  // coverage and depth samples per pixel of the visibility buffer (1 = none).
  int msaa_samples = 1;
  // The engine's kernels' precision ("precision": {"resolve": "float" |
  // "fixed"}): the resolve from linear radiance to 8-bit sRGB through float
  // arithmetic on each value (DisplayTransform), or through the value's
  // 16-bit HDR code (hdr16) and one table of 65536 codes (Hdr16Display).
  bool fixed_resolve = false;
  // "precision": {"depth": "float32" | "unorm24" | "float24"}: the visibility
  // buffer's depth format (depth_format.h).
  DepthFormat depth_format = DepthFormat::Float32;
  // "precision": {"attributes": "float32" | "float16"}: the shade pass's
  // interpolated normal, tangent, UVs and colour rounded to fp16 (mediump
  // varyings); positions and UV derivatives stay float.
  bool half_attributes = false;
  nlohmann::json plugins = nlohmann::json::object();  // raw plugin sections by name

  // The internal size: round(render_scale * width) x round(render_scale * height), at least 1x1.
  int render_width() const { return scaled_extent(width, render_scale); }
  int render_height() const { return scaled_extent(height, render_scale); }
  // Whether the internal size differs from the output's (an upscale runs).
  bool scaled() const { return render_width() != width || render_height() != height; }
  static int scaled_extent(int extent, float scale);
};

// Loads and validates a profile file. `plugin_sections` lists the section
// names that registered plugins accept. Throws InputError.
Profile load_profile(const std::string& path, const std::vector<std::string>& plugin_sections);
// Same, from an already parsed document (`path` is used in messages).
Profile parse_profile(const nlohmann::json& doc, const std::string& path,
                      const std::vector<std::string>& plugin_sections);

}  // namespace cr
