// Profiles: defaults, every engine key, plugin sections, strict errors.
#include <string>

#include <doctest/doctest.h>

#include "engine/core/error.h"
#include "engine/core/profile.h"

namespace {

const std::string kBad = std::string(CR_TEST_DATA_DIR) + "/bad";
const std::vector<std::string> kPlugins = {"atmosphere", "fog"};

std::string parse_error(const nlohmann::json& doc) {
  try {
    cr::parse_profile(doc, "inline.json", kPlugins);
  } catch (const cr::InputError& e) {
    CHECK(e.file() == "inline.json");
    return e.what();
  }
  FAIL("expected InputError for " << doc.dump());
  return "";
}

}  // namespace

TEST_CASE("profile: every engine key is read, plugin sections are kept raw") {
  nlohmann::json doc = {{"name", "mobile"},       {"resolution", {960, 540}}, {"tile_size", 32},
                        {"shadow_map_size", 1024}, {"shadow_distance", 80.5}, {"shadow_pcf_radius", 0},
                        {"frame_budget_ms", 16.6}, {"fog", {{"slices", 32}}}};
  cr::Profile p = cr::parse_profile(doc, "profiles/mobile.json", kPlugins);
  CHECK(p.name == "mobile");
  CHECK(p.path == "profiles/mobile.json");
  CHECK(p.width == 960);
  CHECK(p.height == 540);
  CHECK(p.tile_size == 32);
  CHECK(p.shadow_map_size == 1024);
  CHECK(p.shadow_distance == doctest::Approx(80.5));
  CHECK(p.shadow_pcf_radius == 0);
  CHECK(p.frame_budget_ms == doctest::Approx(16.6));
  CHECK(p.plugins["fog"]["slices"] == 32);
  CHECK_FALSE(p.plugins.contains("atmosphere"));
}

TEST_CASE("profile: missing keys keep their defaults; the name defaults to the file stem") {
  cr::Profile p = cr::parse_profile(nlohmann::json::object(), "profiles/desktop.json", kPlugins);
  cr::Profile defaults;
  CHECK(p.name == "desktop");
  CHECK(p.width == defaults.width);
  CHECK(p.tile_size == defaults.tile_size);
  CHECK(p.shadow_map_size == defaults.shadow_map_size);
  CHECK(cr::parse_profile({{"shadow_map_size", 0}}, "p.json", kPlugins).shadow_map_size == 0);
}

TEST_CASE("profile: out-of-range values and unknown keys name the key") {
  CHECK(parse_error({{"tile_size", 48}}).find("'tile_size'") != std::string::npos);
  CHECK(parse_error({{"tile_size", 512}}).find("'tile_size'") != std::string::npos);
  CHECK(parse_error({{"resolution", {16385, 10}}}).find("'resolution'") != std::string::npos);
  CHECK(parse_error({{"resolution", {640}}}).find("'resolution'") != std::string::npos);
  CHECK(parse_error({{"resolution", {640.5, 360}}}).find("'resolution'") != std::string::npos);
  CHECK(parse_error({{"shadow_map_size", 63}}).find("'shadow_map_size'") != std::string::npos);
  CHECK(parse_error({{"shadow_map_size", 8193}}).find("'shadow_map_size'") != std::string::npos);
  CHECK(parse_error({{"shadow_distance", 0}}).find("'shadow_distance'") != std::string::npos);
  CHECK(parse_error({{"shadow_pcf_radius", 5}}).find("'shadow_pcf_radius'") != std::string::npos);
  CHECK(parse_error({{"texture_decode_budget_mb", -1}}).find("'texture_decode_budget_mb'") != std::string::npos);
  CHECK(parse_error({{"frame_budget_ms", -1}}).find("'frame_budget_ms'") != std::string::npos);
  CHECK(parse_error({{"frame_budget_ms", "fast"}}).find("must be a number") != std::string::npos);
  CHECK(parse_error({{"clouds", {}}}).find("unknown key 'clouds'") != std::string::npos);
  CHECK(parse_error(nlohmann::json::array()).find("JSON object") != std::string::npos);
}

TEST_CASE("profile files: malformed JSON reports the position; bad values name file and key") {
  struct FileCase {
    const char* file;
    const char* error;
  };
  for (const FileCase& c : {FileCase{"profile_malformed.json", "line 1, column"},
                            FileCase{"profile_unknown_key.json", "unknown key 'tile_szie'"},
                            FileCase{"profile_tile_size.json", "'tile_size'"},
                            FileCase{"profile_resolution.json", "'resolution'"},
                            FileCase{"profile_shadow_map_size.json", "'shadow_map_size'"},
                            FileCase{"profile_duplicate_key.json", "key 'tile_size' appears twice"},
                            FileCase{"profile_deep_plugin.json", "more than 128 levels deep"},
                            FileCase{"no_such_profile.json", "cannot open"}}) {
    const std::string path = kBad + "/" + c.file;
    CAPTURE(path);
    try {
      cr::load_profile(path, kPlugins);
      FAIL_CHECK("loaded, but should have been rejected");
    } catch (const cr::InputError& e) {
      std::string what = e.what();
      CAPTURE(what);
      CHECK(e.file() == path);
      CHECK(what.rfind(path + ": ", 0) == 0);
      CHECK(what.find(c.error) != std::string::npos);
    }
  }
}

TEST_CASE("profile: antialiasing names a sample count; anything else names the choices") {
  for (const auto& [name, samples] : std::vector<std::pair<std::string, int>>{{"none", 1}, {"msaa2", 2}, {"msaa4", 4}, {"msaa8", 8}})
    CHECK(cr::parse_profile({{"antialiasing", name}}, "inline.json", kPlugins).msaa_samples == samples);
  CHECK(cr::parse_profile(nlohmann::json::object(), "inline.json", kPlugins).msaa_samples == 1);
  for (const char* bad : {"msaa3", "MSAA4", "fxaa", ""}) {
    const std::string e = parse_error({{"antialiasing", bad}});
    CHECK(e.find("antialiasing") != std::string::npos);
    CHECK(e.find("\"msaa8\"") != std::string::npos);
  }
  CHECK(parse_error({{"antialiasing", 4}}).find("antialiasing") != std::string::npos);
}

TEST_CASE("profile: precision names the resolve's kernel and the depth format, anything else names the choices") {
  CHECK_FALSE(cr::parse_profile(nlohmann::json::object(), "inline.json", kPlugins).fixed_resolve);
  CHECK(cr::parse_profile({{"precision", {{"resolve", "fixed"}}}}, "inline.json", kPlugins).fixed_resolve);
  CHECK_FALSE(cr::parse_profile({{"precision", {{"resolve", "float"}}}}, "inline.json", kPlugins).fixed_resolve);
  const std::string bad_value = parse_error({{"precision", {{"resolve", "half"}}}});
  CHECK(bad_value.find("precision.resolve") != std::string::npos);
  CHECK(bad_value.find("\"fixed\"") != std::string::npos);
  CHECK(cr::parse_profile({{"precision", {{"depth", "unorm24"}}}}, "inline.json", kPlugins).depth_format ==
        cr::DepthFormat::Unorm24);
  CHECK(cr::parse_profile({{"precision", {{"depth", "float24"}}}}, "inline.json", kPlugins).depth_format ==
        cr::DepthFormat::Float24);
  CHECK(parse_error({{"precision", {{"depth", "unorm16"}}}}).find("precision.depth") != std::string::npos);
  CHECK(cr::parse_profile({{"precision", {{"attributes", "float16"}}}}, "inline.json", kPlugins).half_attributes);
  CHECK(parse_error({{"precision", {{"attributes", "half"}}}}).find("precision.attributes") != std::string::npos);
  CHECK(parse_error({{"precision", {{"stencil", "x"}}}}).find("stencil") != std::string::npos);
  CHECK(parse_error({{"precision", "fixed"}}).find("precision") != std::string::npos);
}

TEST_CASE("profile: render_scale is a number in [0.25, 1] that sets the internal size, anything else names the key") {
  const cr::Profile defaults = cr::parse_profile(nlohmann::json::object(), "inline.json", kPlugins);
  CHECK(defaults.render_scale == 1.0f);
  CHECK_FALSE(defaults.scaled());
  const cr::Profile half = cr::parse_profile({{"render_scale", 0.5}, {"resolution", {1280, 720}}}, "inline.json", kPlugins);
  CHECK(half.render_width() == 640);
  CHECK(half.render_height() == 360);
  CHECK(half.scaled());
  // round(0.3 * 101) = 30, round(0.3 * 5) = 2; never below 1.
  const cr::Profile odd = cr::parse_profile({{"render_scale", 0.3}, {"resolution", {101, 5}}}, "inline.json", kPlugins);
  CHECK(odd.render_width() == 30);
  CHECK(odd.render_height() == 2);
  CHECK(cr::parse_profile({{"render_scale", 0.25}, {"resolution", {3, 1}}}, "inline.json", kPlugins).render_height() == 1);
  CHECK(cr::parse_profile({{"render_scale", 1}}, "inline.json", kPlugins).render_scale == 1.0f);
  for (const nlohmann::json& bad : {nlohmann::json(0.2), nlohmann::json(1.01), nlohmann::json(0), nlohmann::json(-0.5)}) {
    const std::string e = parse_error({{"render_scale", bad}});
    CAPTURE(e);
    CHECK(e.find("'render_scale'") != std::string::npos);
    CHECK(e.find("[0.25, 1]") != std::string::npos);
  }
  for (const nlohmann::json& bad : {nlohmann::json("half"), nlohmann::json(true), nlohmann::json::array({0.5})}) {
    const std::string e = parse_error({{"render_scale", bad}});
    CAPTURE(e);
    CHECK(e.find("'render_scale'") != std::string::npos);
    CHECK(e.find("must be a number") != std::string::npos);
  }
  CHECK(parse_error({{"render_scael", 0.5}}).find("render_scale") != std::string::npos);  // listed among the allowed keys
}
