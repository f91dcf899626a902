#pragma once
// Shared by the libFuzzer targets (docs/fuzzing.md): a per-process scratch
// folder for the bytes the engine's loaders read back as files, and the rule
// of what counts as a finding.
//
// Expected outcome of any input: success, or a cr::Error (InputError, ...)
// with a message. A finding: any other exception (std::bad_alloc included),
// a crash, a sanitizer report, a leak, a timeout, or an allocation or RSS
// over libFuzzer's -malloc_limit_mb / -rss_limit_mb.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace cr::fuzz {

// Memory the targets give the engine (MemoryBudget) where it takes a budget:
// 1 GiB, so every legitimate allocation stays under -malloc_limit_mb=1024
// and a run stays under -rss_limit_mb=2048.
inline constexpr size_t kMemoryBudgetBytes = size_t(1) << 30;

// Sets options.memory = &budget where the options struct has that member
// (GltfLoadOptions gets a MemoryBudget* `memory`), else does nothing: the
// targets follow the loader's budget as soon as it takes one.
template <class Options, class Budget>
void attach_budget(Options& options, Budget& budget) {
  if constexpr (requires { options.memory = &budget; }) options.memory = &budget;
}

// Creates the scratch folder once per process: $CR_FUZZ_TMPDIR, else
// /dev/shm, else $TMPDIR, else /tmp, as cr-fuzz-<pid>-XXXXXX; removed at
// exit, and folders of processes that died (a crash) are removed by the next
// target that starts. Engine warnings (std::cerr) are silenced unless
// CR_FUZZ_VERBOSE is set.
const std::string& scratch_dir();

// Writes `data` to scratch_dir()/name and returns the path.
std::string write_scratch_file(const std::string& name, const uint8_t* data, size_t size);

// Runs `body`: a cr::Error is an expected outcome (printed under
// CR_FUZZ_VERBOSE); any other exception is reported on stderr with its type
// and message, then the process aborts so libFuzzer records the input.
void run_one(const char* target, const std::function<void()>& body);

}  // namespace cr::fuzz
