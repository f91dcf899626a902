// Inputs tinygltf accepted silently, dropping or misreading what the file
// says (issue 22, item 6): each is refused with a message naming the file and
// the JSON field.
#include <string>

#include <doctest/doctest.h>

#include "engine/core/error.h"
#include "engine/scene/gltf_loader.h"
#include "tests/scene/gltf_rejection.h"
#include "tests/scene/gltf_test_builder.h"

namespace {

// A triangle whose buffer is the data URI `uri` (36 bytes of positions).
std::string triangle_with_buffer_uri(const std::string& name, const std::string& uri) {
  cr::test::GltfBuilder b;
  b.doc["nodes"] = {{{"mesh", 0}}};
  b.doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}};
  b.doc["accessors"] = {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}}};
  b.doc["bufferViews"] = {{{"buffer", 0}, {"byteLength", 36}}};
  b.doc["buffers"] = {{{"byteLength", 36}, {"uri", uri}}};
  return b.write(name);
}

const std::string kTriangleBase64 = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";

}  // namespace

TEST_CASE("a node with both a matrix and TRS is refused (tinygltf dropped the TRS)") {
  const std::string path = cr::test::bad_input("node_matrix_and_trs.gltf");
  CHECK(cr::test::gltf_rejection(path) == path + ": invalid glTF: 'nodes[0]' has both 'matrix' and 'translation'; a node's "
                                  "transform is either a matrix or translation/rotation/scale");
}

TEST_CASE("a skin's accessor and node indices out of range are refused") {
  SUBCASE("inverseBindMatrices") {
    const std::string path = cr::test::bad_input("skin_inverse_bind_matrices_out_of_range.gltf");
    CHECK(cr::test::gltf_rejection(path) == path + ": skin 0 inverseBindMatrices: accessor index 5 out of range (2 accessors)");
  }
  SUBCASE("joints") {
    const std::string path = cr::test::bad_input("skin_joint_out_of_range.gltf");
    CHECK(cr::test::gltf_rejection(path) == path + ": skin 0 joint 4 out of range (2 nodes)");
  }
  SUBCASE("skeleton") {
    const std::string path = cr::test::bad_input("skin_skeleton_out_of_range.gltf");
    CHECK(cr::test::gltf_rejection(path) == path + ": skin 0 skeleton 3 out of range (2 nodes)");
  }
}

TEST_CASE("a morph target's accessor is checked even on a primitive that is not drawn, and must be an index") {
  SUBCASE("out of range on a points primitive") {
    const std::string path = cr::test::bad_input("morph_target_out_of_range.gltf");
    CHECK(cr::test::gltf_rejection(path) == path + ": mesh 1 primitive 0 target 0 POSITION: accessor index 7 out of range (2 accessors)");
  }
  SUBCASE("not an integer (tinygltf dropped the attribute)") {
    const std::string path = cr::test::bad_input("morph_target_not_integer.gltf");
    CHECK(cr::test::gltf_rejection(path) == path + ": invalid glTF: 'meshes[0].primitives[0].targets[0].POSITION' must be a "
                                    "non-negative integer, found 0.5");
  }
}

TEST_CASE("fixed-length arrays with the wrong number of components are refused") {
  SUBCASE("baseColorFactor of 3 (tinygltf used white and dropped the texture)") {
    const std::string path = cr::test::bad_input("base_color_factor_3.gltf");
    CHECK(cr::test::gltf_rejection(path) == path + ": invalid glTF: 'materials[0].pbrMetallicRoughness.baseColorFactor' must be "
                                    "an array of 4 numbers, found [1,0.5,0]");
  }
  SUBCASE("emissiveFactor of 2") {
    const std::string path = cr::test::bad_input("emissive_factor_2.gltf");
    CHECK(cr::test::gltf_rejection(path) == path + ": invalid glTF: 'materials[0].emissiveFactor' must be an array of 3 numbers, "
                                    "found [1,1]");
  }
  SUBCASE("a node rotation of 3") {
    cr::test::GltfBuilder b;
    b.doc["nodes"] = {{{"rotation", {0.0, 0.0, 1.0}}}};
    const std::string path = b.write("hardening_rotation_3.gltf");
    CHECK(cr::test::gltf_rejection(path) == path + ": invalid glTF: 'nodes[0].rotation' must be an array of 4 numbers, found [0.0,0.0,1.0]");
  }
}

TEST_CASE("only buffer 0 of a GLB may omit its uri") {
  const std::string path = cr::test::bad_input("glb_second_buffer_without_uri.glb");
  CHECK(cr::test::gltf_rejection(path) == path + ": invalid glTF: 'buffers[1]' has no uri; only buffer 0 of a GLB may leave it out "
                                  "(it is the BIN chunk)");
}

TEST_CASE("data URIs: base64 only, nothing after it, and the MIME types glTF allows") {
  SUBCASE("a buffer with trailing characters") {
    const std::string path = cr::test::bad_input("buffer_data_uri_trailing_garbage.gltf");
    CHECK(cr::test::gltf_rejection(path) == path + ": invalid glTF: 'buffers[0].uri' has 4 characters after its base64 data: \"?v=2\"");
  }
  SUBCASE("a buffer of type image/png") {
    const std::string path = cr::test::bad_input("buffer_data_uri_wrong_mime.gltf");
    CHECK(cr::test::gltf_rejection(path) == path + ": invalid glTF: 'buffers[0].uri' is a data URI of type image/png; a buffer's "
                                    "must be application/octet-stream or application/gltf-buffer");
  }
  SUBCASE("an image of type image/gif") {
    const std::string path = cr::test::bad_input("image_data_uri_wrong_mime.gltf");
    CHECK(cr::test::gltf_rejection(path) == path + ": invalid glTF: 'images[0].uri' is a data URI of type image/gif; an image's "
                                    "must be image/png or image/jpeg");
  }
  SUBCASE("an image with a fragment after its data") {
    const std::string path = cr::test::bad_input("image_data_uri_trailing_garbage.gltf");
    CHECK(cr::test::gltf_rejection(path) == path + ": invalid glTF: 'images[0].uri' has 5 characters after its base64 data: \"#frag\"");
  }
  SUBCASE("a buffer that is not base64") {
    const std::string path = triangle_with_buffer_uri("hardening_uri_not_base64.gltf", "data:application/octet-stream,abc");
    CHECK(cr::test::gltf_rejection(path) == path + ": invalid glTF: 'buffers[0].uri' is a data URI without \";base64,\"; glTF data "
                                    "URIs must be base64");
  }
  SUBCASE("padding in the middle") {
    const std::string path = triangle_with_buffer_uri("hardening_uri_inner_padding.gltf",
                                                      "data:application/gltf-buffer;base64,AA==" + kTriangleBase64);
    CHECK(cr::test::gltf_rejection(path) == path + ": invalid glTF: 'buffers[0].uri' has 48 characters after its base64 data: "
                                    "\"AAAAAAAAAAAAAAAAAACA...\"");
  }
  SUBCASE("both buffer MIME types load") {
    CHECK_NOTHROW(cr::load_gltf(triangle_with_buffer_uri("hardening_uri_gltf_buffer.gltf",
                                                         "data:application/gltf-buffer;base64," + kTriangleBase64)));
    CHECK_NOTHROW(cr::load_gltf(triangle_with_buffer_uri("hardening_uri_octet_stream.gltf",
                                                         "data:application/octet-stream;base64," + kTriangleBase64)));
  }
}
