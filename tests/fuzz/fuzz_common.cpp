#include "tests/fuzz/fuzz_common.h"

#include <cxxabi.h>
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <new>
#include <streambuf>
#include <typeinfo>

#include "engine/core/error.h"

namespace cr::fuzz {

namespace {

namespace fs = std::filesystem;

constexpr const char* kPrefix = "cr-fuzz-";

bool verbose() {
  static const bool v = std::getenv("CR_FUZZ_VERBOSE") != nullptr;
  return v;
}

// A stream buffer that drops everything: the loaders' warnings on std::cerr
// would otherwise be most of a run's output.
class NullBuffer : public std::streambuf {
 protected:
  int overflow(int c) override { return c == EOF ? 0 : c; }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

bool usable_dir(const char* dir) {
  if (dir == nullptr || *dir == '\0') return false;
  std::error_code ec;
  return fs::is_directory(dir, ec) && access(dir, W_OK | X_OK) == 0;
}

std::string base_dir() {
  const char* const candidates[] = {std::getenv("CR_FUZZ_TMPDIR"), "/dev/shm", std::getenv("TMPDIR"), "/tmp"};
  for (const char* d : candidates) {
    if (usable_dir(d)) return d;
  }
  return ".";
}

// Removes cr-fuzz-<pid>-* folders whose process no longer exists (a target
// that crashed, or was killed, cannot clean up after itself).
void remove_dead_folders(const std::string& base) {
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(base, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(kPrefix, 0) != 0) continue;
    const long pid = std::strtol(name.c_str() + std::char_traits<char>::length(kPrefix), nullptr, 10);
    if (pid <= 0 || pid == long(getpid())) continue;
    if (kill(pid_t(pid), 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to judge
    std::error_code ignore;
    fs::remove_all(e.path(), ignore);
  }
}

std::string g_dir;

void remove_scratch_dir() {
  if (g_dir.empty()) return;
  std::error_code ignore;
  fs::remove_all(g_dir, ignore);
}

std::string demangle(const char* name) {
  int status = 0;
  std::unique_ptr<char, void (*)(void*)> d(abi::__cxa_demangle(name, nullptr, nullptr, &status), std::free);
  return status == 0 && d ? d.get() : name;
}

}  // namespace

const std::string& scratch_dir() {
  if (!g_dir.empty()) return g_dir;
  const std::string base = base_dir();
  remove_dead_folders(base);
  std::string templ = base + "/" + kPrefix + std::to_string(getpid()) + "-XXXXXX";
  if (mkdtemp(templ.data()) == nullptr) {
    std::fprintf(stderr, "cr-fuzz: cannot create a scratch folder under %s\n", base.c_str());
    std::abort();
  }
  g_dir = templ;
  std::atexit(remove_scratch_dir);
  if (!verbose()) {
    static NullBuffer null_buffer;
    std::cerr.rdbuf(&null_buffer);
  }
  return g_dir;
}

std::string write_scratch_file(const std::string& name, const uint8_t* data, size_t size) {
  const std::string path = scratch_dir() + "/" + name;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr || (size > 0 && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) {
    std::fprintf(stderr, "cr-fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
  return path;
}

void run_one(const char* target, const std::function<void()>& body) {
  try {
    body();
  } catch (const cr::Error& e) {
    // Expected: the input was refused with a message.
    if (verbose()) std::fprintf(stderr, "cr-fuzz %s: refused: %s\n", target, e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr,
                 "==cr-fuzz== FINDING (%s): an exception other than cr::Error escaped\n"
                 "==cr-fuzz== type: %s\n==cr-fuzz== what(): %s\n",
                 target, demangle(typeid(e).name()).c_str(), e.what());
    std::fflush(stderr);
    std::abort();
  }
  // Anything that is not a std::exception propagates and terminates: also a finding.
}

}  // namespace cr::fuzz
