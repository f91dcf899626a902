// Crafted malformed glTF files (tests/data/bad): each is rejected with an
// InputError that names the file and the fault.
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "engine/core/error.h"
#include "engine/scene/gltf_loader.h"
#include "tests/scene/expect_gltf_rejected.h"

TEST_CASE("crafted malformed glTF files give an InputError naming the file and the fault") {
  struct BadCase {
    const char* file;
    const char* error;
  };
  const std::vector<BadCase> cases = {
      {"truncated.glb", "truncated"},
      {"malformed_json.gltf", "line 1, column"},
      {"index_out_of_range.gltf", "index 2 has value 7, out of range for 3 vertices"},
      {"nan_position.gltf", "vertex 1 is not finite"},
      {"node_cycle.gltf", "cycle"},
      {"two_parents.gltf", "node 2 has two parents"},
      {"missing_buffer.gltf", "no_such_buffer.bin"},
      {"accessor_out_of_bounds.gltf", "needs 48 bytes but bufferView 0 has 36"},
      {"stride_too_small.gltf", "byteStride 8"},
      {"huge_count.gltf", "above the limit"},
      {"material_out_of_range.gltf", "material 3 out of range"},
      {"mesh_out_of_range.gltf", "node 0 mesh 2 out of range"},
      {"texture_out_of_range.gltf", "texture index 5 out of range"},
      {"position_wrong_component_type.gltf", "expected FLOAT"},
      {"triangle_count_not_multiple_of_3.gltf", "not a multiple of 3"},
      {"huge_image.gltf", "20000x20000"},
      {"missing_image.gltf", "no_such_texture.png"},
      {"does_not_exist.gltf", "file not found"},
      {"deep_extras.gltf", "more than 128 levels deep"},
  };
  for (const BadCase& c : cases) {
    const std::string path = std::string(CR_TEST_DATA_DIR) + "/bad/" + c.file;
    CAPTURE(path);
    expect_gltf_rejected(path, c.error);
  }
}
