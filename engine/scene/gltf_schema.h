#pragma once
// JSON-level validation of a glTF document before tinygltf converts it.
// tinygltf silently replaces a property of the wrong type by its default (a
// "primitives" object instead of an array becomes a mesh with no primitives,
// a string "scale" becomes 1.0), which would render a different scene than the
// file describes. This checks the type of every core property the loader uses
// (and the size of fixed-size arrays), that extension values are objects, that
// no required extension is one the loader lacks, and what tinygltf would lose:
// a node's TRS beside its matrix, data URIs of the wrong type or with
// characters after their base64 data. Messages name the property path.
#include <string>

#include <nlohmann/json.hpp>

namespace cr {

// The extensions the loader implements (the set in gltf_schema.cpp; docs/scene.md "Supported").
bool gltf_extension_supported(const std::string& name);

// Throws InputError(path, "... 'meshes[0].primitives' must be an array ...").
void validate_gltf_schema(const std::string& path, const nlohmann::json& doc);

}  // namespace cr
