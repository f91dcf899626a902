#include <doctest/doctest.h>

#include <stdexcept>

#include "engine/core/error.h"
#include "engine/output/atomic_file.h"
#include "tests/output/scratch_dir.h"

using cr::test::ScratchDir;

TEST_CASE("atomic write replaces the content and leaves no temporary file") {
  ScratchDir dir("atomic-replace");
  const std::string path = dir.file("report.json");
  cr::write_file_atomic(path, "first version, longer than the second");
  cr::write_file_atomic(path, "second");
  CHECK(cr::read_file_bytes(path) == "second");
  CHECK(dir.entries() == std::vector<std::string>{"report.json"});
}

TEST_CASE("a failing writer callback leaves the old file intact") {
  ScratchDir dir("atomic-callback");
  const std::string path = dir.file("golden.exr");
  cr::write_file_atomic(path, "old golden");
  std::string seen_temp;
  CHECK_THROWS_AS(cr::write_file_atomic(path,
                                        [&](const std::string& temp) {
                                          seen_temp = temp;
                                          cr::write_file_atomic(temp, "half a file");
                                          throw std::runtime_error("render crashed");
                                        }),
                  std::runtime_error);
  CHECK(seen_temp != path);
  CHECK(seen_temp.rfind(path + ".tmp.", 0) == 0);  // same directory, unique suffix
  CHECK(cr::read_file_bytes(path) == "old golden");
  CHECK(dir.entries() == std::vector<std::string>{"golden.exr"});
}

TEST_CASE("a writer callback that writes nothing is an error, not an empty file") {
  ScratchDir dir("atomic-nothing");
  const std::string path = dir.file("out.bin");
  CHECK_THROWS_AS(cr::write_file_atomic(path, [](const std::string&) {}), cr::Error);
  CHECK(dir.entries().empty());
}

TEST_CASE("atomic write into a missing directory names the path and the system error") {
  ScratchDir dir("atomic-missing");
  const std::string path = dir.file("no/such/dir/out.png");
  try {
    cr::write_file_atomic(path, "data");
    FAIL("expected cr::Error");
  } catch (const cr::Error& e) {
    const std::string what = e.what();
    CHECK(what.find(path) != std::string::npos);
    CHECK(what.find("No such file or directory") != std::string::npos);
  }
  CHECK(dir.entries().empty());
}

TEST_CASE("reading a missing file is an InputError naming it") {
  ScratchDir dir("atomic-read");
  const std::string path = dir.file("absent.txt");
  try {
    cr::read_file_bytes(path);
    FAIL("expected cr::InputError");
  } catch (const cr::InputError& e) {
    CHECK(e.file() == path);
  }
  CHECK_THROWS_AS(cr::read_file_bytes(dir.file("")), cr::InputError);  // a directory
}
