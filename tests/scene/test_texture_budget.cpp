// The texture budget (GltfLoadOptions::texture_decode_budget, the profile's
// texture_decode_budget_mb): the decoded images' RGBA8 chains fit it, the
// largest dropping top levels first; a warning names each image dropped and
// the size it loads at; the memory report charges what is kept.
#include <iostream>
#include <sstream>
#include <string>

#include <doctest/doctest.h>

#include "engine/core/memory_budget.h"
#include "engine/output/png_io.h"
#include "engine/scene/gltf_loader.h"
#include "tests/scene/gltf_test_builder.h"

namespace {

// A w x h RGBA PNG of varied texels, written beside the test's glTF files.
std::string write_test_png(const std::string& name, int w, int h) {
  cr::Image8 image{w, h, 4, {}};
  for (int i = 0; i < w * h * 4; ++i) image.data.push_back(uint8_t((i * 53 + w) % 256));
  cr::write_png(cr::test::test_output_dir() + "/" + name, image);
  return name;
}

// A triangle whose material reads a 64x64 base colour (sRGB) and a 16x16
// metallic-roughness image (linear).
std::string write_model() {
  cr::test::GltfBuilder b;
  const int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  const int normal = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3", 3);
  const int uv = b.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2);
  b.add("meshes", {{"primitives", {{{"attributes", {{"POSITION", pos}, {"NORMAL", normal}, {"TEXCOORD_0", uv}}},
                                    {"material", 0}}}}});
  b.add("nodes", {{"mesh", 0}});
  b.add("materials", {{"pbrMetallicRoughness",
                       {{"baseColorTexture", {{"index", 0}}}, {"metallicRoughnessTexture", {{"index", 1}}}}}});
  b.add("textures", {{"source", 0}});
  b.add("textures", {{"source", 1}});
  b.add("images", {{"uri", write_test_png("budget_large.png", 64, 64)}, {"name", "large"}});
  b.add("images", {{"uri", write_test_png("budget_small.png", 16, 16)}});
  return b.write("texture_budget.gltf");
}

struct Load {
  cr::Scene scene;
  std::string warnings;
  cr::MemoryBudget memory{0};  // unlimited: charges are recorded
};

void load(const std::string& path, size_t budget, Load& out) {
  cr::GltfLoadOptions options;
  options.texture_decode_budget = budget;
  options.memory = &out.memory;
  std::ostringstream warnings;
  std::streambuf* saved = std::cerr.rdbuf(warnings.rdbuf());
  try {
    out.scene = cr::load_gltf(path, options);
  } catch (...) {
    std::cerr.rdbuf(saved);
    throw;
  }
  std::cerr.rdbuf(saved);
  out.warnings = warnings.str();
}

size_t chain_bytes(const cr::Image& image) {
  size_t bytes = 0;
  for (const cr::MipLevel& m : image.mips) bytes += m.rgba.size();
  return bytes;
}

const cr::MemoryBudget::Charge& image_charge(const cr::MemoryBudget& memory, int source) {
  for (const cr::MemoryBudget::Charge& c : memory.charges())
    if (c.field == "images[" + std::to_string(source) + "]") return c;
  FAIL("no charge for images[" << source << "]");
  return memory.charges().front();
}

}  // namespace

TEST_CASE("images over the texture budget load at lower levels, largest first, with a warning and charges that match") {
  const std::string path = write_model();
  // Chains: 64x64 is 4 x 5461 = 21844 bytes, 16x16 4 x 341 = 1364.
  Load full;
  load(path, size_t(512) << 20, full);
  REQUIRE(full.scene.images.size() == 2);
  const cr::Image& large = full.scene.images[0];
  const cr::Image& small = full.scene.images[1];
  CHECK(large.srgb);
  CHECK(large.mips[0].width == 64);
  CHECK(small.mips[0].width == 16);
  CHECK(full.warnings.empty());
  CHECK(chain_bytes(large) == 21844);
  CHECK(image_charge(full.memory, 0).bytes == 21844);
  CHECK(image_charge(full.memory, 0).what == "image 0 'large' (64x64 RGBA8 with mips)");
  CHECK(image_charge(full.memory, 1).bytes == 1364);

  SUBCASE("the largest image drops its top level, and only it, until the chains fit") {
    // 23208 bytes in all; with 64x64 at 32x32 (5460) they take 6824.
    Load fit;
    load(path, 8000, fit);
    const cr::Image& dropped = fit.scene.images[0];
    REQUIRE(dropped.mips.size() == large.mips.size() - 1);
    for (size_t l = 0; l < dropped.mips.size(); ++l) {
      CHECK(dropped.mips[l].width == large.mips[l + 1].width);
      CHECK(dropped.mips[l].rgba == large.mips[l + 1].rgba);  // the full chain's level, exactly
    }
    CHECK(fit.scene.images[1].mips.size() == small.mips.size());
    CHECK(fit.warnings == path + ": warning: the images' mip chains (23 KiB as RGBA8) exceed the texture budget "
                                 "(texture_decode_budget_mb, 8 KiB): image 0 'large' (sRGB) loads at 32x32 (of 64x64); "
                                 "7 KiB kept\n");
    CHECK(image_charge(fit.memory, 0).bytes == chain_bytes(dropped));
    CHECK(image_charge(fit.memory, 0).bytes == 5460);
    CHECK(image_charge(fit.memory, 0).what == "image 0 'large' (64x64 loaded at 32x32 RGBA8 with mips)");
    CHECK(image_charge(fit.memory, 1).bytes == chain_bytes(fit.scene.images[1]));
  }

  SUBCASE("images of one size shrink together; nothing goes below 1x1") {
    // 1500 bytes: 64x64 goes to 16x16 (1364), then the two 16x16 chains are
    // the largest in turn, the earlier image's first: both end at 8x8 (340).
    Load tight;
    load(path, 1500, tight);
    CHECK(tight.scene.images[0].mips[0].width == 8);
    CHECK(tight.scene.images[1].mips[0].width == 8);
    CHECK(tight.warnings.find("image 0 'large' (sRGB) loads at 8x8 (of 64x64); image 1 (linear) loads at 8x8 (of "
                              "16x16); 680 bytes kept") != std::string::npos);
    Load none;
    load(path, 0, none);
    for (int i = 0; i < 2; ++i) {
      const cr::Image& image = none.scene.images[size_t(i)];
      REQUIRE(image.mips.size() == 1);
      CHECK(image.mips[0].width == 1);
      CHECK(image.mips[0].height == 1);
      CHECK(image_charge(none.memory, i).bytes == 4);
    }
    // The 1x1 level is the full chain's: the image's average.
    CHECK(none.scene.images[0].mips[0].rgba == large.mips.back().rgba);
  }
}
