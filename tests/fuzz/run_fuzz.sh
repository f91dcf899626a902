#!/usr/bin/env bash
# Builds and runs the libFuzzer targets (docs/fuzzing.md).
#   tests/fuzz/run_fuzz.sh TARGET SECONDS [-j N] [-- LIBFUZZER_ARGS...]
#       A long run of one target (gltf, scene, profile, image) for SECONDS
#       with N parallel jobs (default 1; libFuzzer's fork mode): it goes on
#       after a finding, growing build-fuzz/corpus/TARGET and writing every
#       finding to build-fuzz/crashes/TARGET/ (crash-*, leak-*, oom-*,
#       timeout-*). Exit status 1 when the run added a finding there.
#   tests/fuzz/run_fuzz.sh --ci SECONDS
#       The CI stage: every target for SECONDS each, one job, fixed seed,
#       from the seed corpus alone (a scratch corpus, removed first); stops
#       at the first finding and fails with its report.
#   tests/fuzz/run_fuzz.sh --build
#       Only configures and builds build-fuzz and the seed corpus
#       (build-fuzz/corpus/seeds/TARGET, tests/fuzz/make_corpus.sh).
# Environment: CR_FUZZ_BUILD (build folder, default build-fuzz),
# CR_FUZZ_CRASHES (findings folder, default $CR_FUZZ_BUILD/crashes),
# CR_FUZZ_BUILD_JOBS (compile jobs, default nproc), CR_FUZZ_SEED (libFuzzer
# -seed of a long run; default random).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
build=${CR_FUZZ_BUILD:-$root/build-fuzz}
crashes=${CR_FUZZ_CRASHES:-$build/crashes}
targets=(gltf scene profile image)

usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 2; }

# clang and the libFuzzer runtime (Debian 12: clang 14), installed like
# tests/setup_debian.sh installs the rest.
ensure_clang() {
  local missing=()
  for p in clang libclang-rt-14-dev; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "installing: ${missing[*]}"
    local sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
  fi
}

build_targets() {
  ensure_clang
  local launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  # -O1 -g1 and unity batches as the sanitizer builds of run_all.sh; no NDEBUG,
  # so assertions are findings too.
  cmake -S . -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Fuzz -DCMAKE_CXX_FLAGS="-O1 -g1" \
        -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=8 -DCR_FUZZ=ON "${launcher[@]}" >/dev/null
  cmake --build "$build" -j"${CR_FUZZ_BUILD_JOBS:-$(nproc)}" --target fuzz_targets
  # The seeds are rebuilt every time (a few seconds): new bad inputs join at once.
  tests/fuzz/make_corpus.sh "$build/corpus/seeds" "$build"
}

max_len() {
  case $1 in
    gltf) echo 1048576 ;;   # libFuzzer's default cap; larger seeds (default.glb) are cut there
    image) echo 65536 ;;
    *) echo 65536 ;;
  esac
}

# Options every run uses: the memory limits (the engine gets a 1 GiB
# MemoryBudget, fuzz_common.h), a time limit per input, the dictionary.
common_args() {
  echo -rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=30 -max_len="$(max_len "$1")" \
       -dict="$root/tests/fuzz/$1.dict" -print_final_stats=1
}

export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

run_ci() {
  local seconds=$1 failed=0
  build_targets
  for t in "${targets[@]}"; do
    local work=$build/ci/$t log=$build/ci/$t.log
    rm -rf "$work"; mkdir -p "$work" "$crashes/$t"
    echo "-- fuzz_$t: ${seconds} s"
    # shellcheck disable=SC2046
    if "$build/tests/fuzz/fuzz_$t" $(common_args "$t") -seed=1 -max_total_time="$seconds" \
         -artifact_prefix="$crashes/$t/" "$work" "$build/corpus/seeds/$t" >"$log" 2>&1; then
      grep -E '^stat::(number_of_executed_units|average_exec_per_sec|peak_rss_mb)|^#[0-9]+ +DONE' "$log" | tr '\n' ' '
      echo
    else
      failed=1
      echo "fuzz_$t: FINDING (input saved under $crashes/$t/; log $log):"
      grep -E -A40 '==cr-fuzz==|ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error|Test unit written|SUMMARY' "$log" | head -80
    fi
  done
  return $failed
}

run_long() {
  local t=$1 seconds=$2 jobs=$3; shift 3
  case " ${targets[*]} " in *" $t "*) ;; *) echo "unknown target '$t' (one of: ${targets[*]})" >&2; exit 2 ;; esac
  build_targets
  mkdir -p "$build/corpus/$t" "$crashes/$t" "$build/logs"
  local before after seed=()
  before=$(find "$crashes/$t" -type f | wc -l)
  [ -n "${CR_FUZZ_SEED:-}" ] && seed=(-seed="$CR_FUZZ_SEED")
  local log
  log=$build/logs/$t-$(date +%Y%m%d-%H%M%S).log
  echo "fuzz_$t: $seconds s, $jobs job(s); corpus $build/corpus/$t, findings $crashes/$t/, log $log"
  # Fork mode: the run goes on after a finding (each is written out) and
  # merges what the jobs find into the corpus.
  # shellcheck disable=SC2046
  (cd "$build/logs" && "$build/tests/fuzz/fuzz_$t" $(common_args "$t") "${seed[@]}" -max_total_time="$seconds" \
     -fork="$jobs" -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1 \
     -artifact_prefix="$crashes/$t/" "$@" "$build/corpus/$t" "$build/corpus/seeds/$t") 2>&1 | tee "$log" \
     | grep -E --line-buffered '^#[0-9]+|==cr-fuzz==|ERROR:|SUMMARY|Test unit written|INFO: (Seed|fork)' || true
  after=$(find "$crashes/$t" -type f | wc -l)
  echo "corpus: $(find "$build/corpus/$t" -type f | wc -l) inputs; findings in $crashes/$t/: $after ($((after - before)) new)"
  [ "$after" -eq "$before" ]
}

[ $# -ge 1 ] || usage
case $1 in
  --build) build_targets ;;
  --ci) [ $# -eq 2 ] || usage; run_ci "$2" ;;
  -h|--help) usage ;;
  *)
    [ $# -ge 2 ] || usage
    t=$1 seconds=$2 jobs=1; shift 2
    if [ "${1:-}" = "-j" ]; then jobs=${2:?-j needs a number}; shift 2; fi
    [ "${1:-}" = "--" ] && shift
    run_long "$t" "$seconds" "$jobs" "$@"
    ;;
esac
