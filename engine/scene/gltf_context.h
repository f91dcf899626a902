#pragma once
// Shared state of one glTF load: the parsed model, the file name for messages,
// and the error/warning channel every loading stage reports through.
#include <string>

#include <tiny_gltf.h>

namespace cr {

struct GltfContext {
  const tinygltf::Model& model;
  std::string path;

  // Throws InputError(path, what).
  [[noreturn]] void fail(const std::string& what) const;
  // Prints "path: warning: what" to stderr.
  void warn(const std::string& what) const;
};

// "mesh 3 'Body'" style labels for messages; the name is omitted when empty.
std::string gltf_label(const char* kind, size_t index, const std::string& name);

}  // namespace cr
