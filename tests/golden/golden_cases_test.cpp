// The parts of the golden run below the command: which frames a scene keeps,
// case discovery and filtering, tolerance validation, and the bitwise buffer
// comparison behind the 1 vs N threads check.
#include <doctest/doctest.h>

#include <filesystem>

#include "engine/cli/golden_cases.h"
#include "engine/cli/golden_render.h"
#include "engine/cli/golden_tolerances.h"
#include "engine/core/error.h"
#include "engine/output/atomic_file.h"
#include "tests/output/scratch_dir.h"

using cr::test::ScratchDir;

TEST_CASE("golden frames: still scenes keep frame 0, paths and plugin scenes a later frame too") {
  CHECK(cr::golden_last_frame(1, false) == 0);
  CHECK(cr::golden_last_frame(1, true) == cr::kGoldenLaterFrame);  // temporal plugins under a still camera
  CHECK(cr::golden_last_frame(3, false) == 2);
  CHECK(cr::golden_last_frame(48, false) == cr::kGoldenLaterFrame);
  CHECK(cr::golden_last_frame(48, true) == cr::kGoldenLaterFrame);
}

TEST_CASE("golden cases: every scene under every profile, sorted, with file names per kept frame") {
  ScratchDir dir("golden-cases");
  const std::string glb = std::string(CR_BINARY_DIR) + "/scenes/default.glb";
  std::filesystem::create_directories(dir.file("scenes"));
  std::filesystem::create_directories(dir.file("profiles"));
  cr::write_file_atomic(dir.file("scenes/b_path.json"),
                        R"({"gltf": ")" + glb + R"(", "frames": 30, "camera": {"keys": [
                            {"frame": 0, "position": [0, 5, 14], "target": [0, 0, 0]}]}})");
  cr::write_file_atomic(dir.file("scenes/a_still.json"), R"({"gltf": ")" + glb + R"("})");
  cr::write_file_atomic(dir.file("scenes/notes.txt"), "not a scene");
  cr::write_file_atomic(dir.file("profiles/mobile.json"), "{}");
  cr::write_file_atomic(dir.file("profiles/desktop.json"), "{}");

  const auto cases = cr::discover_golden_cases(dir.file("scenes"), dir.file("profiles"), {});
  REQUIRE(cases.size() == 4);
  CHECK(cases[0].name() == "a_still.desktop");
  CHECK(cases[1].name() == "a_still.mobile");
  CHECK(cases[2].name() == "b_path.desktop");
  CHECK(cases[3].name() == "b_path.mobile");
  CHECK(cases[0].kept_frames == std::vector<int>{0});
  CHECK(cases[2].last_frame == cr::kGoldenLaterFrame);
  CHECK(cases[2].kept_frames == std::vector<int>{0, cr::kGoldenLaterFrame});
  CHECK(cr::golden_file_name(cases[3], 8) == "b_path.mobile.f0008.png");

  CHECK(cr::filter_golden_cases(cases, "*.mobile").size() == 2);
  CHECK(cr::filter_golden_cases(cases, "b_path.desktop").size() == 1);
  CHECK(cr::filter_golden_cases(cases, "c*").empty());

  std::filesystem::create_directories(dir.file("golden"));
  for (const char* name : {"a_still.desktop.f0000.png", "b_path.mobile.f0008.png", "b_path.mobile.f0004.png",
                           "old.desktop.f0000.png", "tolerances.json"})
    cr::write_file_atomic(dir.file("golden/") + name, "");
  CHECK(cr::find_stale_goldens(dir.file("golden"), cases) ==
        std::vector<std::string>{"b_path.mobile.f0004.png", "old.desktop.f0000.png"});
  CHECK(cr::find_stale_goldens(dir.file("nowhere"), cases).empty());

  CHECK_THROWS_AS(cr::discover_golden_cases(dir.file("nowhere"), dir.file("profiles"), {}), cr::InputError);
  std::filesystem::create_directories(dir.file("empty"));
  CHECK_THROWS_AS(cr::discover_golden_cases(dir.file("scenes"), dir.file("empty"), {}), cr::InputError);
}

TEST_CASE("golden tolerances: per-profile entries with a reason for every value, default otherwise") {
  ScratchDir dir("golden-tolerances");
  const std::string why =
      R"("why": {"max_abs": "a", "rmse": "b", "pixel_threshold": "c", "max_fraction": "d", "flip_mean": "e"})";
  cr::write_file_atomic(dir.file("t.json"), R"({"comment": "x", "profiles": {
      "default": {"max_abs": 0.5, "rmse": 0.01, "pixel_threshold": 0.01, "max_fraction": 0.002, "flip_mean": 0.01, )" +
                                                why + R"(},
      "mobile": {"max_abs": 0.25, "rmse": 0.02, "pixel_threshold": 0.02, "max_fraction": 0.004, "flip_mean": 0.02, )" +
                                                why + "}}}");
  const cr::GoldenTolerances t = cr::GoldenTolerances::load(dir.file("t.json"));
  CHECK(t.for_profile("mobile").entry == "mobile");
  CHECK(t.for_profile("mobile").thresholds.max_abs == 0.25);
  CHECK(t.for_profile("desktop").entry == "default");
  CHECK(t.for_profile("desktop").thresholds.max_fraction == 0.002);

  auto fails_naming = [&](const std::string& text, const std::string& field) {
    cr::write_file_atomic(dir.file("bad.json"), text);
    try {
      cr::GoldenTolerances::load(dir.file("bad.json"));
      FAIL("expected an InputError naming " << field);
    } catch (const cr::InputError& e) {
      CHECK_MESSAGE(std::string(e.what()).find(field) != std::string::npos, e.what());
    }
  };
  fails_naming(R"({"profiles": {}})", "default");
  fails_naming(R"({"profiles": {"default": {"max_abs": 0.5, "rmse": 0.01, "pixel_threshold": 0.01,
               "max_fraction": 0.002, "flip_mean": 0.01}}})", "why");
  fails_naming(R"({"profiles": {"default": {"max_abs": 2, "rmse": 0.01, "pixel_threshold": 0.01,
               "max_fraction": 0.002, "flip_mean": 0.01, )" + why + "}}}", "max_abs");
  fails_naming(R"({"profiles": {"default": {"max_abs": 0.5, "rmse": 0.01, "pixel_threshold": 0.01,
               "max_fraction": 0.002, "flip_mean": 0.01, "why": {"max_abs": "", "rmse": "b",
               "pixel_threshold": "c", "max_fraction": "d", "flip_mean": "e"}}}})", "max_abs");
  fails_naming(R"({"profiles": {"default": {"max_abs": 0.5, "rmse": 0.01, "pixel_threshold": 0.01,
               "max_fraction": 0.002, "flip_mean": 0.01, "psnr": 30, )" + why + "}}}", "psnr");
  fails_naming(R"({"tolerances": {}})", "tolerances");
}

TEST_CASE("golden determinism check compares buffers bit for bit and names the first difference") {
  cr::FrameBuffers a;
  a.resize(4, 3);
  cr::FrameBuffers b = a;
  CHECK(cr::describe_buffer_difference(a, b).empty());

  b.color[b.index(2, 1)].g = -0.0f;  // == 0.0f, yet a different bit pattern
  const std::string colour = cr::describe_buffer_difference(a, b);
  CHECK(colour.find("colour differs in 1 pixel, first at (2, 1)") != std::string::npos);
  CHECK(colour.find("display") == std::string::npos);

  b = a;
  b.display[b.index(3, 2) * 3 + 2] = 1;
  b.display[b.index(1, 2) * 3] = 1;
  CHECK(cr::describe_buffer_difference(a, b) == "display differs in 2 pixels, first at (1, 2)");

  b = a;
  b.distance[0] = 5.0f;
  CHECK(cr::describe_buffer_difference(a, b).find("distance") != std::string::npos);
}
