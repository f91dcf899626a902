// libFuzzer target: image bytes -> the loader's PNG/JPEG path. The bytes
// become the one image of a minimal GLB (a bufferView image used as a
// material's base colour texture), so they go through exactly what a model's
// image goes through: capture_gltf_image (header, format and size checks),
// decode_gltf_image (stb_image) and mips (top levels dropped where the
// texture budget asks), under the loader's own limits and memory budget.
#include <cstring>
#include <string>
#include <vector>

#include "engine/core/memory_budget.h"
#include "engine/scene/gltf_loader.h"
#include "tests/fuzz/fuzz_common.h"

namespace {

void put_le32(std::vector<uint8_t>& out, size_t v) {
  for (int k = 0; k < 4; ++k) out.push_back(uint8_t(v >> (8 * k)));
}

std::vector<uint8_t> wrap_in_glb(const uint8_t* data, size_t size) {
  const bool jpeg = size >= 2 && data[0] == 0xFF && data[1] == 0xD8;
  const std::string n = std::to_string(size);
  std::string json =
      "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":" + n +
      "}],\"bufferViews\":[{\"buffer\":0,\"byteLength\":" + n + "}],\"images\":[{\"bufferView\":0,\"mimeType\":\"" +
      (jpeg ? "image/jpeg" : "image/png") +
      "\"}],\"textures\":[{\"source\":0}],\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}]}";
  while (json.size() % 4 != 0) json += ' ';
  const size_t bin = (size + 3) & ~size_t(3);
  std::vector<uint8_t> out;
  out.reserve(28 + json.size() + bin);
  out.insert(out.end(), {'g', 'l', 'T', 'F'});
  put_le32(out, 2);
  put_le32(out, 12 + 8 + json.size() + 8 + bin);
  put_le32(out, json.size());
  put_le32(out, 0x4E4F534Au);  // "JSON"
  out.insert(out.end(), json.begin(), json.end());
  put_le32(out, bin);
  put_le32(out, 0x004E4942u);  // "BIN\0"
  out.insert(out.end(), data, data + size);
  out.resize(out.size() + (bin - size), 0);
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> glb = wrap_in_glb(data, size);
  const std::string path = cr::fuzz::write_scratch_file("image.glb", glb.data(), glb.size());
  cr::fuzz::run_one("image", [&] {
    cr::MemoryBudget budget(cr::fuzz::kMemoryBudgetBytes);
    cr::GltfLoadOptions options;
    cr::fuzz::attach_budget(options, budget);
    (void)cr::load_gltf(path, options);
  });
  return 0;
}
