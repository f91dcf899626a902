#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "engine/core/error.h"
#include "engine/output/atomic_file.h"
#include "engine/output/exr_io.h"
#include "tests/output/scratch_dir.h"

using cr::test::ScratchDir;

namespace {

cr::ExrImage test_render(int width, int height) {
  cr::ExrImage image;
  image.color = cr::ImageRGBf(width, height);
  for (size_t i = 0; i < image.color.rgb.size(); ++i)
    image.color.rgb[i] = 0.001f * static_cast<float>(i * i % 977) + static_cast<float>(i % 5) * 10.0f;
  for (int i = 0; i < width * height; ++i)
    image.depth.push_back(i % 7 == 0 ? std::numeric_limits<float>::infinity() : 0.1234567f * i);
  cr::ExrChannel fog{"fog.transmittance", cr::ExrPixelType::Float, {}};
  for (int i = 0; i < width * height; ++i) fog.values.push_back(1.0f / (1.0f + i));
  image.aovs.push_back(fog);
  return image;
}

}  // namespace

TEST_CASE("EXR round trip: colour within half precision, depth and AOVs exact") {
  ScratchDir dir("exr-roundtrip");
  const cr::ExrImage original = test_render(13, 7);
  cr::write_exr(dir.file("frame.exr"), original);
  CHECK(dir.entries() == std::vector<std::string>{"frame.exr"});

  const cr::ExrImage read = cr::read_exr(dir.file("frame.exr"));
  CHECK(read.color.width == 13);
  CHECK(read.color.height == 7);
  REQUIRE(read.color.rgb.size() == original.color.rgb.size());
  for (size_t i = 0; i < read.color.rgb.size(); ++i) {
    const float expected = original.color.rgb[i];
    // half: 11 significant bits, relative error <= 2^-11 for normal values
    CHECK(std::abs(read.color.rgb[i] - expected) <= std::abs(expected) * 0x1p-11f + 1e-7f);
  }
  CHECK(read.depth == original.depth);  // float: bit exact, +inf included
  REQUIRE(read.aovs.size() == 1);
  CHECK(read.aovs[0].name == "fog.transmittance");
  CHECK(read.aovs[0].values == original.aovs[0].values);
}

TEST_CASE("an EXR without depth has no Z on reading") {
  ScratchDir dir("exr-nodepth");
  cr::ExrImage image;
  image.color = cr::ImageRGBf(3, 2);
  cr::write_exr(dir.file("c.exr"), image);
  const cr::ExrImage read = cr::read_exr(dir.file("c.exr"));
  CHECK(read.depth.empty());
  CHECK(read.aovs.empty());
}

TEST_CASE("an EXR missing a colour channel is an InputError naming file and channel") {
  ScratchDir dir("exr-missing");
  const std::string path = dir.file("rg.exr");
  cr::write_exr_channels(path, 2, 2,
                         {{"R", cr::ExrPixelType::Half, {1, 2, 3, 4}},
                          {"G", cr::ExrPixelType::Half, {1, 2, 3, 4}}});
  try {
    cr::read_exr(path);
    FAIL("expected cr::InputError");
  } catch (const cr::InputError& e) {
    CHECK(e.file() == path);
    CHECK(std::string(e.what()).find("'B'") != std::string::npos);
  }
}

TEST_CASE("unreadable EXR files are InputErrors naming the file") {
  ScratchDir dir("exr-bad");
  cr::write_exr(dir.file("good.exr"), test_render(16, 16));
  const std::string good = cr::read_file_bytes(dir.file("good.exr"));
  cr::write_file_atomic(dir.file("truncated.exr"), good.substr(0, good.size() / 2));
  cr::write_file_atomic(dir.file("text.exr"), "not an exr");
  cr::write_file_atomic(dir.file("empty.exr"), "");
  for (const char* name : {"truncated.exr", "text.exr", "empty.exr", "missing.exr"}) {
    const std::string path = dir.file(name);
    try {
      cr::read_exr(path);
      FAIL("expected cr::InputError for " << name);
    } catch (const cr::InputError& e) {
      CHECK(e.file() == path);
    }
  }
}

TEST_CASE("inconsistent EXR data throws and writes nothing") {
  ScratchDir dir("exr-inconsistent");
  cr::ExrImage image = test_render(4, 4);
  image.depth.pop_back();
  CHECK_THROWS_AS(cr::write_exr(dir.file("bad.exr"), image), cr::Error);
  image = test_render(4, 4);
  image.aovs.push_back({"Z", cr::ExrPixelType::Float, std::vector<float>(16)});
  CHECK_THROWS_AS(cr::write_exr(dir.file("bad.exr"), image), cr::Error);
  CHECK(dir.entries().empty());
}
