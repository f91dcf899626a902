// `cpurender compare` as a command: exit codes, the heat map written on
// failure only, and metrics in its JSON equal to hand-computed values.
// (compare_images itself is tested in tests/output/image_compare_test.cpp.)
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>

#include "engine/cli/compare_command.h"
#include "engine/core/json_input.h"
#include "engine/output/atomic_file.h"
#include "engine/output/png_io.h"
#include "tests/output/scratch_dir.h"

using cr::test::ScratchDir;

namespace {

// A 4x2 RGB8 image with every channel at `code`.
cr::Image8 flat(uint8_t code) {
  return cr::Image8{4, 2, 3, std::vector<uint8_t>(4 * 2 * 3, code)};
}

void set(cr::Image8& image, int x, int y, int channel, uint8_t code) {
  image.data[(size_t(y) * image.width + x) * 3 + channel] = code;
}

bool exists(const std::string& path) { return std::filesystem::exists(path); }

}  // namespace

TEST_CASE("compare command: identical images exit 0 and write no heat map") {
  ScratchDir dir("golden-compare-same");
  cr::write_png(dir.file("a.png"), flat(100));
  CHECK(cr::compare_command({dir.file("a.png"), dir.file("a.png"), "--diff", dir.file("d.png")}) == 0);
  CHECK_FALSE(exists(dir.file("d.png")));
  CHECK_FALSE(exists(dir.file("a.diff.png")));
}

TEST_CASE("compare command: a one-pixel change above threshold exits 1 and writes the heat map") {
  ScratchDir dir("golden-compare-pixel");
  cr::Image8 changed = flat(100);
  set(changed, 2, 1, 1, 200);
  cr::write_png(dir.file("ref.png"), flat(100));
  cr::write_png(dir.file("test.png"), changed);

  // Default diff path: TEST without extension + .diff.png.
  CHECK(cr::compare_command({dir.file("ref.png"), dir.file("test.png")}) == 1);
  REQUIRE(exists(dir.file("test.diff.png")));
  for (const char* kind : {"abs", "flip"}) {
    CAPTURE(kind);
    CHECK(cr::compare_command({dir.file("ref.png"), dir.file("test.png"), "--diff", dir.file("heat.png"),
                               "--diff-kind", kind}) == 1);
    const cr::Image8 heat = cr::read_png(dir.file("heat.png"));
    CHECK(heat.width == 4);
    CHECK(heat.height == 2);
    auto brightness = [&](int x, int y) {
      const uint8_t* p = &heat.data[(size_t(y) * heat.width + x) * heat.channels];
      return p[0] + p[1] + p[2];
    };
    CHECK(brightness(2, 1) > brightness(0, 0) + 100);
  }
  // The same change passes when the thresholds allow it.
  CHECK(cr::compare_command({dir.file("ref.png"), dir.file("test.png"), "--max-abs", "0.5", "--rmse", "0.5",
                             "--max-fraction", "0.2", "--flip", "1", "--diff", dir.file("none.png")}) == 0);
  CHECK_FALSE(exists(dir.file("none.png")));
}

TEST_CASE("compare command: a global offset of one code passes the default thresholds") {
  ScratchDir dir("golden-compare-offset");
  cr::write_png(dir.file("a.png"), flat(100));
  cr::write_png(dir.file("b.png"), flat(101));
  CHECK(cr::compare_command({dir.file("a.png"), dir.file("b.png")}) == 0);
  CHECK_FALSE(exists(dir.file("b.diff.png")));
  // ... and fails once a strict RMSE is asked for: the offset is measured.
  CHECK(cr::compare_command({dir.file("a.png"), dir.file("b.png"), "--rmse", "0.001"}) == 1);
}

TEST_CASE("compare command: JSON metrics equal hand-computed values") {
  ScratchDir dir("golden-compare-json");
  cr::Image8 test = flat(100);
  set(test, 0, 0, 0, 151);  // +51 codes = 0.2
  set(test, 3, 1, 2, 75);   // -25 codes
  cr::write_png(dir.file("ref.png"), flat(100));
  cr::write_png(dir.file("test.png"), test);
  CHECK(cr::compare_command({dir.file("ref.png"), dir.file("test.png"), "--pixel-threshold", "0.15", "--json",
                             dir.file("m.json"), "--diff", dir.file("d.png")}) == 1);
  const nlohmann::json doc = cr::load_json_file(dir.file("m.json"));
  const nlohmann::json& m = doc["metrics"];
  const double a = 51.0 / 255.0, b = 25.0 / 255.0;
  const double rmse = std::sqrt((a * a + b * b) / 24.0);  // 8 pixels x 3 channels
  CHECK(m["max_abs"].get<double>() == doctest::Approx(a).epsilon(1e-6));
  CHECK(m["max_abs_rgb"][0].get<double>() == doctest::Approx(a).epsilon(1e-6));
  CHECK(m["max_abs_rgb"][1].get<double>() == 0.0);
  CHECK(m["max_abs_rgb"][2].get<double>() == doctest::Approx(b).epsilon(1e-6));
  CHECK(m["rmse"].get<double>() == doctest::Approx(rmse).epsilon(1e-6));
  CHECK(m["psnr_db"].get<double>() == doctest::Approx(-20.0 * std::log10(rmse)).epsilon(1e-6));
  CHECK(m["pixels_over_threshold"].get<int>() == 1);  // only 0.2 > 0.15
  CHECK(m["fraction_over_threshold"].get<double>() == 0.125);
  CHECK(doc["pass"] == false);
  CHECK(exists(dir.file("d.png")));
}

TEST_CASE("compare command: usage and input errors exit 2 without writing a heat map") {
  ScratchDir dir("golden-compare-errors");
  cr::write_png(dir.file("a.png"), flat(100));
  cr::write_png(dir.file("wide.png"), cr::Image8{5, 2, 3, std::vector<uint8_t>(30, 100)});
  cr::write_file_atomic(dir.file("text.png"), "not an image\n");
  const std::string a = dir.file("a.png");

  CHECK(cr::compare_command({"--help"}) == 0);
  CHECK(cr::compare_command({}) == 2);
  CHECK(cr::compare_command({a}) == 2);
  CHECK(cr::compare_command({a, a, a}) == 2);
  CHECK(cr::compare_command({a, a, "--bogus", "1"}) == 2);
  CHECK(cr::compare_command({a, a, "--rmse", "abc"}) == 2);
  CHECK(cr::compare_command({a, a, "--rmse", "-1"}) == 2);
  CHECK(cr::compare_command({a, a, "--rmse"}) == 2);
  CHECK(cr::compare_command({a, a, "--diff-kind", "rainbow"}) == 2);
  CHECK(cr::compare_command({a, dir.file("missing.png"), "--diff", dir.file("d.png")}) == 2);
  CHECK(cr::compare_command({a, dir.file("wide.png"), "--diff", dir.file("d.png")}) == 2);
  CHECK(cr::compare_command({a, dir.file("text.png"), "--diff", dir.file("d.png")}) == 2);
  CHECK(cr::compare_command({dir.file("text.png"), a, "--diff", dir.file("d.png")}) == 2);
  CHECK_FALSE(exists(dir.file("d.png")));
}
