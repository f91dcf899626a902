#pragma once
// Asserts that loading a glTF fails with one InputError that names the file
// first and contains the expected fault.
#include <string>

#include <doctest/doctest.h>

#include "engine/core/error.h"
#include "engine/scene/gltf_loader.h"

inline void expect_gltf_rejected(const std::string& path, const std::string& expected_fault) {
  try {
    cr::load_gltf(path);
    FAIL_CHECK("loaded, but should have been rejected");
  } catch (const cr::InputError& e) {
    const std::string what = e.what();
    CAPTURE(what);
    CHECK(e.file() == path);
    CHECK(what.rfind(path + ": ", 0) == 0);
    CHECK(what.find(expected_fault) != std::string::npos);
  }
}
