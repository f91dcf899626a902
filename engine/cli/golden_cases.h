#pragma once
// The golden-image cases: every shipped scene under every shipped profile.
// They are found by listing the scenes/ and profiles/ directories rather than
// a manifest, so a scene or profile added to the project is covered without a
// second edit that could be forgotten.
#include <string>
#include <vector>

namespace cr {

// Scenes with a camera path or plugin sections render frames 0..last in order
// (so schedules, history and reprojection run) and keep frame 0 and `last`;
// `last` is this many frames in at most: past the fog's 7-frame jitter cycle
// and a LUT update period or two, yet cheap enough for every CI run.
constexpr int kGoldenLaterFrame = 8;

struct GoldenCase {
  std::string scene;         // scene file stem, e.g. "default_flythrough"
  std::string profile;       // profile file stem, e.g. "desktop"
  std::string scene_path;
  std::string profile_path;
  int last_frame = 0;        // frames 0..last_frame are rendered
  std::vector<int> kept_frames;  // compared with goldens: {0} or {0, last_frame}
  std::string error;             // why the scene file could not be loaded (the case is then an error)

  std::string name() const { return scene + "." + profile; }
};

// The frame a scene's path is rendered to (see kGoldenLaterFrame): 0 for a
// still scene without plugins.
int golden_last_frame(int scene_frames, bool has_plugin_sections);

// "<scene>.<profile>.f0008.png"
std::string golden_file_name(const GoldenCase& c, int frame);

// Every (scene, profile) pair of the *.json files in the two directories,
// sorted by scene then profile. Scene files are loaded (not their glTF) to
// learn their frame counts; an invalid one gives cases carrying its error, so
// the other cases still run. Throws InputError for a missing directory or a
// directory without .json files.
std::vector<GoldenCase> discover_golden_cases(const std::string& scenes_dir,
                                              const std::string& profiles_dir,
                                              const std::vector<std::string>& plugin_sections);

// The cases whose name ("<scene>.<profile>") matches a shell glob pattern.
std::vector<GoldenCase> filter_golden_cases(const std::vector<GoldenCase>& cases,
                                            const std::string& pattern);

// PNG files in `dir` that are no case's golden (sorted names; empty when the
// directory does not exist). Any frame of a case whose scene failed to load
// counts as its golden: its frames are unknown.
std::vector<std::string> find_stale_goldens(const std::string& dir, const std::vector<GoldenCase>& cases);

}  // namespace cr
