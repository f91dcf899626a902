// Messages for inputs that used to mislead: a resolution that overflowed int,
// an option whose value is the next option, an empty value, a number beyond
// double in a JSON file, a directory given as a JSON file, an allocation
// that fails.
#include <doctest/doctest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <new>
#include <sstream>

#include "engine/cli/arg_parser.h"
#include "engine/cli/cli_common.h"
#include "engine/cli/command_registry.h"
#include "engine/cli/module_truth.h"
#include "engine/cli/commands.h"
#include "engine/core/error.h"
#include "engine/core/json_input.h"

namespace {

std::string usage_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const cr::UsageError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("CLI: resolutions are digits within 1..16384 each, never wrapped") {
  CHECK(cr::parse_resolution("1280x720", "render") == std::pair{1280, 720});
  CHECK(cr::parse_resolution("16384x1", "render") == std::pair{16384, 1});
  for (const char* bad : {"4294967360x36", "64x4294967332", "-64x36", "+64x36", " 64x36", "64x36 ", "64X36", "64x",
                          "x36", "0x36", "16385x1", "64x36x2", "6.4x36", ""})
    CHECK(usage_error([&] { cr::parse_resolution(bad, "render"); }).find("--resolution expects WxH") !=
          std::string::npos);
}

TEST_CASE("CLI: an option's value is never the next option, and never empty") {
  auto parse = [](std::vector<std::string> args) {
    cr::ArgParser p("render", "render [SCENE]", "");
    p.option("resolution", "WxH", "size").option("out", "DIR", "output", "out").option("format", "LIST", "f", "png");
    p.parse(args, 0, 1);
  };
  CHECK(usage_error([&] { parse({"--resolution", "--out", "dir"}); }).find("--resolution needs a value") !=
        std::string::npos);
  CHECK(usage_error([&] { parse({"--format", ""}); }).find("--format needs a value") != std::string::npos);
  CHECK(usage_error([&] { parse({"--format="}); }).find("--format needs a value") != std::string::npos);
  CHECK_NOTHROW(parse({"--resolution", "64x36", "--out", "dir"}));
}

TEST_CASE("JSON files: a number beyond double and a directory name the file") {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "cr_cli_messages_test";
  std::filesystem::create_directories(dir);
  const std::string file = (dir / "big.json").string();
  std::ofstream(file) << R"({"exposure_ev100": 1e999})";
  try {
    (void)cr::load_json_file(file);
    FAIL_CHECK("1e999 was accepted");
  } catch (const cr::InputError& e) {
    CHECK(e.file() == file);
    CHECK(std::string(e.what()).find("malformed JSON") != std::string::npos);
  }
  try {
    (void)cr::load_json_file(dir.string());
    FAIL_CHECK("a directory was read as JSON");
  } catch (const cr::InputError& e) {
    CHECK(std::string(e.what()).find("is a directory") != std::string::npos);
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("CLI: std::bad_alloc reaches the user as an out-of-memory message and exit code 2") {
  const std::filesystem::path log = std::filesystem::temp_directory_path() / "cr_cli_bad_alloc.txt";
  std::fflush(stderr);
  const int saved = dup(2);
  FILE* f = std::fopen(log.c_str(), "w");
  REQUIRE(f);
  dup2(fileno(f), 2);
  char cmd[] = "cpurender", name[] = "oom";
  char* argv[] = {cmd, name};
  const int rc = cr::run_cli(2, argv, [](cr::PluginRegistry&, cr::CommandRegistry& commands, cr::ModuleTruthRegistry&) {
    commands.add({"oom", "throws std::bad_alloc", [](const std::vector<std::string>&) -> int { throw std::bad_alloc(); }});
  });
  std::fflush(stderr);
  dup2(saved, 2);
  close(saved);
  std::fclose(f);
  std::stringstream text;
  text << std::ifstream(log).rdbuf();
  CHECK(rc == 2);
  CHECK(text.str().find("cpurender: error: out of memory: an allocation failed") == 0);
  CHECK(text.str().find("std::bad_alloc") == std::string::npos);
}
