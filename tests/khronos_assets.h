#pragma once
// Third-party sample models for tests (README "Third-party models"): found
// under $CR_ASSETS_DIR, never copied into the repository. A test whose model
// is absent says so and passes as skipped.
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include <doctest/doctest.h>

namespace cr::test {

// $CR_ASSETS_DIR/<relative> when it exists; otherwise nullopt after a
// "skipped" message naming the file.
inline std::optional<std::string> asset_path(const std::string& relative) {
  const char* dir = std::getenv("CR_ASSETS_DIR");
  const std::string path = dir ? std::string(dir) + "/" + relative : "";
  if (!dir || !std::filesystem::exists(path)) {
    MESSAGE("skipped: " << relative << " not found (set CR_ASSETS_DIR to the shared assets directory)");
    return std::nullopt;
  }
  return path;
}

}  // namespace cr::test
