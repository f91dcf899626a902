#include <doctest/doctest.h>

#include <filesystem>

#include "engine/core/error.h"
#include "engine/output/atomic_file.h"
#include "engine/output/png_io.h"
#include "tests/output/scratch_dir.h"

using cr::test::ScratchDir;

namespace {

cr::Image8 test_pattern(int width, int height) {
  cr::Image8 image{width, height, 3, {}};
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c)
        image.data.push_back(static_cast<uint8_t>((x * 37 + y * 11 + c * 85) & 0xff));
  return image;
}

void check_input_error_names(const std::string& path) {
  try {
    cr::read_png(path);
    FAIL("expected cr::InputError for " << path);
  } catch (const cr::InputError& e) {
    CHECK(e.file() == path);
  }
}

}  // namespace

TEST_CASE("PNG round trip is exact") {
  ScratchDir dir("png-roundtrip");
  const cr::Image8 original = test_pattern(17, 9);
  cr::write_png(dir.file("pattern.png"), original);
  const cr::Image8 read = cr::read_png(dir.file("pattern.png"));
  CHECK(read.width == 17);
  CHECK(read.height == 9);
  CHECK(read.channels == 3);
  CHECK(read.data == original.data);
  CHECK(dir.entries() == std::vector<std::string>{"pattern.png"});

  const cr::ImageRGBf floats = cr::read_png_rgb(dir.file("pattern.png"));
  REQUIRE(floats.rgb.size() == original.data.size());
  CHECK(floats.rgb[5] == doctest::Approx(original.data[5] / 255.0));
}

TEST_CASE("display values quantise to the nearest 8-bit code and clamp") {
  cr::ImageRGBf display(2, 1);
  display.rgb = {0.0f, 0.5f, 1.0f, -0.2f, 1.7f, 0.25f};
  const cr::Image8 image = cr::to_rgb8(display);
  CHECK(image.data == std::vector<uint8_t>{0, 128, 255, 0, 255, 64});
}

TEST_CASE("broken PNG files are InputErrors naming the file") {
  ScratchDir dir("png-bad");
  cr::write_png(dir.file("good.png"), test_pattern(32, 32));
  const std::string good = cr::read_file_bytes(dir.file("good.png"));

  cr::write_file_atomic(dir.file("truncated.png"), good.substr(0, good.size() / 2));
  check_input_error_names(dir.file("truncated.png"));
  cr::write_file_atomic(dir.file("text.png"), "this is not an image\n");
  check_input_error_names(dir.file("text.png"));
  cr::write_file_atomic(dir.file("empty.png"), "");
  check_input_error_names(dir.file("empty.png"));
  cr::write_file_atomic(dir.file("signature_only.png"), good.substr(0, 8));
  check_input_error_names(dir.file("signature_only.png"));
  check_input_error_names(dir.file("missing.png"));
}

TEST_CASE("writing an inconsistent PNG throws and writes nothing") {
  ScratchDir dir("png-inconsistent");
  cr::Image8 image = test_pattern(4, 4);
  image.data.pop_back();
  CHECK_THROWS_AS(cr::write_png(dir.file("bad.png"), image), cr::Error);
  CHECK(dir.entries().empty());
}
