#!/usr/bin/env bash
# The test command of the README: set-up, release build, all tests; then the
# unit tests under AddressSanitizer+UndefinedBehaviorSanitizer and the
# threading tests under ThreadSanitizer; then a short run of each fuzz target
# (clang, libFuzzer: tests/fuzz, docs/fuzzing.md).
#   tests/run_all.sh            everything (what CI runs)
#   tests/run_all.sh --quick    release build and tests only
set -euo pipefail
cd "$(dirname "$0")/.."
./tests/setup_debian.sh
jobs=$(nproc)
# Optional third-party models (README: "Third-party models"): a checkout next
# to ../shared/assets uses them unless CR_ASSETS_DIR says otherwise.
if [ -z "${CR_ASSETS_DIR:-}" ] && [ -d ../shared/assets ]; then
  CR_ASSETS_DIR=$(cd ../shared/assets && pwd)
  export CR_ASSETS_DIR
fi

build_and_test() {  # dir, build type, sanitizer, "targets" (empty = all), ctest args...
  local dir=$1 type=$2 san=$3 targets=$4; shift 4
  # Sanitizer builds: -O1 and line tables only (-g1) compile much faster than
  # RelWithDebInfo and still give symbolised stack traces.
  local flags=""
  [ "$type" = "Sanitize" ] && flags="-O1 -g1"
  # Unity builds: batches of 8 sources per translation unit parse the shared
  # headers once a batch; a clean ASan build of a part takes about half the
  # CPU time. CI only: a developer's edit would recompile the whole batch.
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE="$type" -DCMAKE_CXX_FLAGS="$flags" -DSANITIZE="$san" \
        -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=8 >/dev/null
  if [ -n "$targets" ]; then
    # shellcheck disable=SC2086
    cmake --build "$dir" -j"$jobs" --target $targets
  else
    cmake --build "$dir" -j"$jobs"
  fi
  (cd "$dir" && ctest --output-on-failure -j"$jobs" "$@")
}

# Each stage prints the seconds since the start, so a slow CI run shows where
# its time went.
stage() { echo "== [${SECONDS} s] $*"; }

stage "release build and all tests"
build_and_test build Release "" ""
[ "${1:-}" = "--quick" ] && { stage "release stage passed"; exit 0; }

# The report tests run Python and Chromium, no instrumented code: release only.
stage "AddressSanitizer + UndefinedBehaviorSanitizer"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  build_and_test build-asan Sanitize "address,undefined" "" -LE "slow|report|scaleout"

stage "ThreadSanitizer (job system, frame graph, determinism across thread counts)"
TSAN_OPTIONS=halt_on_error=1 build_and_test build-tsan Sanitize thread \
  "scene_assets test_core test_render test_raster test_fog test_atmosphere" -R "threading|determinism|bit-identical"

stage "fuzzing: each libFuzzer target for 10 s from the seed corpus, fixed seed (docs/fuzzing.md)"
CR_FUZZ_BUILD_JOBS=$jobs ./tests/fuzz/run_fuzz.sh --ci 10
stage "all stages passed"
