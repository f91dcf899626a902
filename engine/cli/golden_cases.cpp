#include "engine/cli/golden_cases.h"

#include <fnmatch.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>

#include "engine/cli/paths.h"
#include "engine/core/error.h"
#include "engine/scene/scene_description.h"

namespace cr {

namespace fs = std::filesystem;

namespace {

std::vector<fs::path> json_files(const std::string& dir, const std::string& what) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError(dir, "the " + what + " directory does not exist");
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ".json") files.push_back(e.path());
  if (files.empty()) throw InputError(dir, "contains no " + what + " (*.json)");
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

int golden_last_frame(int scene_frames, bool has_plugin_sections) {
  // Plugins may be temporal even under a still camera (LUT update schedules,
  // fog history with jitter), so their scenes get a later frame too.
  if (scene_frames > 1) return std::min(scene_frames - 1, kGoldenLaterFrame);
  return has_plugin_sections ? kGoldenLaterFrame : 0;
}

std::string golden_file_name(const GoldenCase& c, int frame) {
  char suffix[32];
  std::snprintf(suffix, sizeof suffix, ".f%04d.png", frame);
  return c.name() + suffix;
}

std::vector<GoldenCase> discover_golden_cases(const std::string& scenes_dir,
                                              const std::string& profiles_dir,
                                              const std::vector<std::string>& plugin_sections) {
  const std::vector<fs::path> scenes = json_files(scenes_dir, "scenes");
  const std::vector<fs::path> profiles = json_files(profiles_dir, "profiles");
  std::vector<GoldenCase> cases;
  for (const fs::path& scene : scenes) {
    int last = 0;
    std::string error;
    try {
      const SceneDescription d = load_scene_description(scene.string(), plugin_sections, scene_asset_dirs());
      last = golden_last_frame(d.frames, !d.plugins.empty());
    } catch (const Error& e) {
      error = e.what();
    }
    for (const fs::path& profile : profiles) {
      GoldenCase c;
      c.scene = scene.stem().string();
      c.profile = profile.stem().string();
      c.scene_path = scene.string();
      c.profile_path = profile.string();
      c.last_frame = last;
      c.error = error;
      c.kept_frames = last > 0 ? std::vector<int>{0, last} : std::vector<int>{0};
      cases.push_back(std::move(c));
    }
  }
  return cases;
}

std::vector<GoldenCase> filter_golden_cases(const std::vector<GoldenCase>& cases, const std::string& pattern) {
  std::vector<GoldenCase> kept;
  for (const GoldenCase& c : cases)
    if (fnmatch(pattern.c_str(), c.name().c_str(), 0) == 0) kept.push_back(c);
  return kept;
}

std::vector<std::string> find_stale_goldens(const std::string& dir, const std::vector<GoldenCase>& cases) {
  std::set<std::string> expected, unknown_frames;
  for (const GoldenCase& c : cases) {
    for (int f : c.kept_frames) expected.insert(golden_file_name(c, f));
    if (!c.error.empty()) unknown_frames.insert(c.name() + ".f");
  }
  auto is_expected = [&](const std::string& name) {
    if (expected.count(name)) return true;
    for (const std::string& prefix : unknown_frames)
      if (name.rfind(prefix, 0) == 0) return true;
    return false;
  };
  std::vector<std::string> stale;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return stale;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && e.path().extension() == ".png" && !is_expected(name)) stale.push_back(name);
  }
  std::sort(stale.begin(), stale.end());
  return stale;
}

}  // namespace cr
