#pragma once
// What the bad-input tests of the glTF loader share: the crafted inputs in
// tests/data/bad and the message a load of one gives.
#include <string>

#include <doctest/doctest.h>

#include "engine/core/error.h"
#include "engine/scene/gltf_loader.h"

namespace cr::test {

inline std::string bad_input(const std::string& name) { return std::string(CR_TEST_DATA_DIR) + "/bad/" + name; }

// The message of the InputError loading `path` throws (naming `path`), "" when it loads.
inline std::string gltf_rejection(const std::string& path, const GltfLoadOptions& options = {}) {
  try {
    (void)load_gltf(path, options);
  } catch (const InputError& e) {
    CHECK(e.file() == path);
    return e.what();
  }
  return "";
}

}  // namespace cr::test
