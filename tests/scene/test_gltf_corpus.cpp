// Debian's assimp-testmodels glTF 2.0 files: the well-formed ones load, the
// malformed ones fail with an InputError naming the file and the fault.
#include <filesystem>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "engine/core/error.h"
#include "engine/scene/gltf_loader.h"
#include "tests/scene/expect_gltf_rejected.h"

namespace {

struct CorpusCase {
  const char* file;       // relative to CR_ASSIMP_GLTF_DIR
  const char* error;      // nullptr: loads; else a substring of the message
  size_t triangles = 0;   // expected triangle count when it loads
};

// What is wrong with each malformed file, as found by reading it:
const std::vector<CorpusCase> kCorpus = {
    {"BoxTextured-glTF/BoxTextured.gltf", nullptr, 12},
    {"BoxTextured-glTF-Embedded/BoxTextured.gltf", nullptr, 12},
    {"BoxTextured-glTF-Binary/BoxTextured.glb", nullptr, 12},
    {"BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf", nullptr, 12},  // extension used, not required
    {"BoxTexcoords-glTF/boxTexcoords.gltf", nullptr, 12},  // texCoord 1: reads TEXCOORD_1
    {"2CylinderEngine-glTF-Binary/2CylinderEngine.glb", nullptr, 121496},
    {"ClearCoat-glTF/ClearCoatTest.gltf", nullptr, 37116},
    {"textureTransform/TextureTransformTest.gltf", nullptr, 24},
    {"cameras/Cameras.gltf", nullptr, 2},
    {"simple_skin/simple_skin.gltf", nullptr, 8},
    {"glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf", nullptr, 12},
    {"TestNoRootNode/SceneWithoutNodes.gltf", nullptr, 0},
    // Four normals are (0,0,0): replaced by generated normals with a warning.
    {"BoxBadNormals-glTF-Binary/BoxBadNormals.glb", nullptr, 12},
    // Requires KHR_technique_webgl.
    {"BoxTextured-glTF-techniqueWebGL/BoxTextured.gltf", "KHR_technique_webgl"},
    // Draco: its encoder dropped the plain file's 10,419 degenerate triangles per mesh (121,496 there).
    {"draco/2CylinderEngine.gltf", nullptr, 110336},
    // Vertex positions contain Inf/NaN.
    {"BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "POSITION: vertex 0 is not finite"},
    // Indices 255 / 65535 for a 24-vertex mesh.
    {"IndexOutOfRange/IndexOutOfRange.gltf", "out of range for 24 vertices"},
    {"IndexOutOfRange/AllIndicesOutOfRange.gltf", "out of range for 24 vertices"},
    // bufferViews reach past its 514-byte buffer (and one triangle list has 35 vertices).
    {"IncorrectVertexArrays/Cube.gltf", "bufferViews[2] (byteOffset 504, byteLength 432) does not fit in buffer 0"},
    // Its .bin file is absent.
    {"MissingBin/BoxTextured.gltf", "BoxTextured0.bin"},
    // Node 0 and node 1 are each other's child.
    {"RecursiveNodes/RecursiveNodes.gltf", "cycle"},
    // "scene": "hello".
    {"SchemaFailures/sceneWrongType.gltf", "'scene' must be a non-negative integer"},
    // "scene": 0 with no scenes array.
    {"TestNoRootNode/NoScene.gltf", "scene 0 out of range"},
    // A primitive without TEXCOORD_0 whose material has a base colour texture.
    {"issue_3269/texcoord_crash.gltf", "no TEXCOORD_0"},
    // Properties of the wrong JSON type, which tinygltf alone would silently default.
    {"wrongTypes/badArray.gltf", "'meshes[0].primitives' must be an array"},
    {"wrongTypes/badExtension.gltf", "KHR_texture_transform' must be an object"},
    {"wrongTypes/badNumber.gltf", "materials[0].normalTexture"},
    {"wrongTypes/badObject.gltf", "'materials[0].pbrMetallicRoughness' must be an object"},
    {"wrongTypes/badString.gltf", "'scenes[0].name' must be a string"},
    {"wrongTypes/badUint.gltf", "baseColorTexture.index' must be a non-negative integer"},
};

}  // namespace

TEST_CASE("assimp glTF 2.0 corpus: well-formed files load, malformed ones are rejected clearly") {
  const std::string dir = CR_ASSIMP_GLTF_DIR;
  if (!std::filesystem::exists(dir)) {
    MESSAGE("skipped: " << dir << " (Debian package assimp-testmodels) is not installed");
    return;
  }
  for (const CorpusCase& c : kCorpus) {
    const std::string path = dir + "/" + c.file;
    CAPTURE(path);
    if (!c.error) {
      cr::Scene s;
      CHECK_NOTHROW(s = cr::load_gltf(path));
      CHECK(s.triangle_count() == c.triangles);
      continue;
    }
    expect_gltf_rejected(path, c.error);
  }
}
