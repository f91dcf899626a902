#include "engine/core/profile.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "engine/core/error.h"
#include "engine/core/json_input.h"

namespace cr {

namespace {

bool is_power_of_two(int v) { return v > 0 && (v & (v - 1)) == 0; }

}  // namespace

int Profile::scaled_extent(int extent, float scale) {
  return std::max(1, int(std::lround(double(scale) * double(extent))));
}

Profile parse_profile(const nlohmann::json& doc, const std::string& path,
                      const std::vector<std::string>& plugin_sections) {
  JsonObject root(doc, path, "");
  Profile p;
  p.path = path;
  p.name = std::filesystem::path(path).stem().string();

  for (const std::string& key : root.keys()) {
    if (key == "name") {
      p.name = root.string("name");
      if (p.name.empty()) root.fail(key, "must not be empty");
    } else if (key == "resolution") {
      const nlohmann::json& v = doc.at(key);
      if (!v.is_array() || v.size() != 2) root.fail(key, "must be [width, height], found " + v.dump());
      for (const nlohmann::json& e : v) {
        bool ok = e.is_number_integer() && e.get<long long>() >= 1 && e.get<long long>() <= 16384;
        if (!ok) root.fail(key, "must be [width, height] with integers in [1, 16384], found " + v.dump());
      }
      p.width = v[0].get<int>();
      p.height = v[1].get<int>();
    } else if (key == "tile_size") {
      p.tile_size = root.integer("tile_size", 8, 256);
      if (!is_power_of_two(p.tile_size)) root.fail(key, "must be a power of two in [8, 256], found " + std::to_string(p.tile_size));
    } else if (key == "shadow_map_size") {
      p.shadow_map_size = root.integer("shadow_map_size", 0, 8192);
      if (p.shadow_map_size != 0 && p.shadow_map_size < 64) {
        root.fail(key, "must be 0 (no shadows) or in [64, 8192], found " + std::to_string(p.shadow_map_size));
      }
    } else if (key == "shadow_distance") {
      p.shadow_distance = static_cast<float>(root.number("shadow_distance", {0.0, 1e9, true}));
    } else if (key == "shadow_pcf_radius") {
      p.shadow_pcf_radius = root.integer("shadow_pcf_radius", 0, 4);
    } else if (key == "texture_decode_budget_mb") {
      p.texture_decode_budget_mb = root.integer("texture_decode_budget_mb", 0, 1 << 20);
    } else if (key == "render_scale") {
      p.render_scale = static_cast<float>(root.number("render_scale", {0.25, 1.0}));
    } else if (key == "frame_budget_ms") {
      p.frame_budget_ms = static_cast<float>(root.number("frame_budget_ms", {0.0, 1e9, true}));
    } else if (key == "antialiasing") {
      const std::string s = root.string("antialiasing");
      if (s == "none") {
        p.msaa_samples = 1;
      } else if (s == "msaa2" || s == "msaa4" || s == "msaa8") {
        p.msaa_samples = s[4] - '0';
      } else {
        root.fail(key, "must be \"none\", \"msaa2\", \"msaa4\" or \"msaa8\", found \"" + s + "\"");
      }
    } else if (key == "precision") {
      const JsonObject precision = root.object("precision");
      precision.allow_only({"resolve", "depth", "attributes"});
      if (precision.has("resolve")) {
        const std::string s = precision.string("resolve");
        if (s != "float" && s != "fixed")
          precision.fail("resolve", "must be \"float\" or \"fixed\", found \"" + s + "\"");
        p.fixed_resolve = s == "fixed";
      }
      if (precision.has("depth")) {
        const std::string s = precision.string("depth");
        if (s == "float32") p.depth_format = DepthFormat::Float32;
        else if (s == "unorm24") p.depth_format = DepthFormat::Unorm24;
        else if (s == "float24") p.depth_format = DepthFormat::Float24;
        else precision.fail("depth", "must be \"float32\", \"unorm24\" or \"float24\", found \"" + s + "\"");
      }
      if (precision.has("attributes")) {
        const std::string s = precision.string("attributes");
        if (s != "float32" && s != "float16")
          precision.fail("attributes", "must be \"float32\" or \"float16\", found \"" + s + "\"");
        p.half_attributes = s == "float16";
      }
    } else if (std::find(plugin_sections.begin(), plugin_sections.end(), key) != plugin_sections.end()) {
      p.plugins[key] = doc.at(key);  // validated by the plugin that owns the section
    } else {
      std::string allowed = "name, resolution, tile_size, shadow_map_size, shadow_distance, "
                            "shadow_pcf_radius, render_scale, frame_budget_ms, texture_decode_budget_mb, antialiasing, "
                            "precision";
      for (const std::string& s : plugin_sections) allowed += ", " + s;
      throw InputError(path, "unknown key '" + key + "' (allowed: " + allowed + ")");
    }
  }
  return p;
}

Profile load_profile(const std::string& path, const std::vector<std::string>& plugin_sections) {
  return parse_profile(load_json_file(path), path, plugin_sections);
}

}  // namespace cr
