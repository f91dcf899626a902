// Nesting depth is limited while parsing (stack overflows in recursive
// walks of deep documents): exactly kMaxJsonDepth levels pass, one more fails.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include "engine/core/error.h"
#include "engine/core/json_input.h"

TEST_CASE("JSON inputs: kMaxJsonDepth levels of nesting parse, one more is an InputError naming the file") {
  const std::string path = (std::filesystem::temp_directory_path() / "cr_json_depth_test.json").string();
  auto nested = [](int levels, char open, char close) {
    std::string s;
    for (int i = 0; i < levels; ++i) s += open == '{' ? std::string("{\"k\":") : std::string(1, open);
    s += "0";
    for (int i = 0; i < levels; ++i) s += close;
    return s;
  };
  for (const auto& [open, close] : {std::pair{'[', ']'}, std::pair{'{', '}'}}) {
    std::ofstream(path) << nested(cr::kMaxJsonDepth, open, close);
    CHECK_NOTHROW((void)cr::load_json_file(path));
    std::ofstream(path) << nested(cr::kMaxJsonDepth + 1, open, close);
    try {
      (void)cr::load_json_file(path);
      FAIL_CHECK("a document nested one level too deep was accepted");
    } catch (const cr::InputError& e) {
      CHECK(e.file() == path);
      CHECK(std::string(e.what()).find("more than 128 levels deep") != std::string::npos);
    }
  }
  std::filesystem::remove(path);
}
