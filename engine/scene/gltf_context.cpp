#include "engine/scene/gltf_context.h"

#include <iostream>

#include "engine/core/error.h"

namespace cr {

void GltfContext::fail(const std::string& what) const { throw InputError(path, what); }

void GltfContext::warn(const std::string& what) const { std::cerr << path << ": warning: " << what << "\n"; }

std::string gltf_label(const char* kind, size_t index, const std::string& name) {
  std::string s = std::string(kind) + " " + std::to_string(index);
  if (!name.empty()) s += " '" + name + "'";
  return s;
}

}  // namespace cr
