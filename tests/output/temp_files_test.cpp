// What a run killed mid-write leaves (NAME.tmp.PID.N) is removed by the next
// atomic write into that folder, but only when its writer is dead.
#include <doctest/doctest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>

#include "engine/output/atomic_file.h"
#include "engine/output/temp_files.h"
#include "tests/output/scratch_dir.h"

using cr::test::ScratchDir;

namespace {

// A PID that was a process and is none now: a child that exited and was reaped.
pid_t dead_pid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  REQUIRE(child > 0);
  int status = 0;
  REQUIRE(::waitpid(child, &status, 0) == child);
  return child;
}

bool has(const ScratchDir& dir, const std::string& name) {
  const std::vector<std::string> names = dir.entries();
  return std::find(names.begin(), names.end(), name) != names.end();
}

}  // namespace

TEST_CASE("temp file names: only NAME.tmp.PID.N names a writer") {
  CHECK(cr::temp_file_writer("frame_0007.exr.tmp.12862.15") == 12862);
  CHECK(cr::temp_file_writer("a.tmp.1.0") == 1);
  const std::string ours = cr::temp_path_for("dir/report.json");
  CHECK(cr::temp_file_writer(ours.substr(4)) == ::getpid());
  for (const char* other : {"frame_0007.exr", ".tmp.12862.15", "frame.tmp.12862", "frame.tmp.12862.",
                            "frame.tmp..15", "frame.tmp.12x.15", "frame.tmp.12862.15.bak", "frame.temp.12862.15",
                            "frame.tmp.0.15", "frame.tmp.99999999999999999999.1", "frame.tmp.-5.1"}) {
    CAPTURE(other);
    CHECK_FALSE(cr::temp_file_writer(other));
  }
}

TEST_CASE("an atomic write removes a dead writer's temp files and keeps a live one's") {
  ScratchDir dir("temp-cleanup");
  const std::string dead_pid_text = std::to_string(dead_pid());
  const std::string dead = "frame_0007.exr.tmp." + dead_pid_text + ".15";
  const std::string live = "frame_0008.exr.tmp." + std::to_string(::getpid()) + ".3";
  const std::string unrelated = "notes.tmp." + dead_pid_text;
  const std::string a_directory = "frame_0009.exr.tmp." + dead_pid_text + ".16";
  for (const std::string& name : {dead, live, unrelated}) std::ofstream(dir.file(name)) << "debris";
  std::filesystem::create_directory(dir.file(a_directory));
  cr::write_file_atomic(dir.file("report.json"), "{}");
  CHECK_FALSE(has(dir, dead));
  CHECK(has(dir, live));         // another run may be writing it
  CHECK(has(dir, unrelated));    // not our pattern
  CHECK(has(dir, a_directory));  // ours are regular files
  CHECK(has(dir, "report.json"));
}

TEST_CASE("a folder is scanned for dead writers' temp files once per process") {
  ScratchDir dir("temp-once");
  cr::write_file_atomic(dir.file("frame_0000.png"), "first");
  const std::string dead = "frame_0001.png.tmp." + std::to_string(dead_pid()) + ".1";
  std::ofstream(dir.file(dead)) << "debris";
  cr::write_file_atomic(dir.file("frame_0002.png"), "second");
  CHECK(has(dir, dead));
}
