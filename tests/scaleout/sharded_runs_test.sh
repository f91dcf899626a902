#!/usr/bin/env bash
# Sharded runs on real engines: a 4-shard sweep and a 4-shard golden check as
# Slurm job arrays on a one-node cluster (slurm_cluster.sh) and as GNU
# parallel jobs, each merged with `cpurender merge` and compared with the
# unsharded run; a 4-shard render of the fog flythrough compared with the
# single-machine frames (bit for bit with the automatic warm-up; within one
# 8-bit code with a 24-frame one).
#   sharded_runs_test.sh CPURENDER
# Exit 0 pass, 77 skip (the cluster cannot run here and nothing failed), 1 fail.
# Every wait is bounded: SHARD_TEST_SLURM_TIMEOUT (s, default 300) for the arrays.
set -uo pipefail

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
SLURM_TIMEOUT=${SHARD_TEST_SLURM_TIMEOUT:-300}

# --slurm WORK CPURENDER: runs under `slurm_cluster.sh run` (SLURM_CONF set):
# submits both arrays and waits for them.
if [ "${1:-}" = --slurm ]; then
  WORK=$2; BIN=$3
  . "$WORK/args.sh"
  mkdir -p "$WORK/slurm"
  ids=""
  for kind in sweep golden; do
    if [ $kind = sweep ]; then args="sweep $SWEEP_ARGS --references $WORK/slurm/references --out $WORK/slurm/sweep.\$SLURM_ARRAY_TASK_ID"
    else args="golden $GOLDEN_ARGS --report $WORK/slurm/golden.\$SLURM_ARRAY_TASK_ID"; fi
    jid=$(timeout 15 sbatch --parsable --array=0-3 --job-name="shard_$kind" --chdir="$WORK/slurm" \
          --output="$WORK/slurm/$kind-%a.log" \
          --wrap "$BIN $args --shard \$SLURM_ARRAY_TASK_ID/4") || { echo "sbatch failed" >&2; exit 1; }
    ids="$ids ${jid%%;*}"
  done
  echo "submitted array jobs:$ids" >&2
  end=$((SECONDS + SLURM_TIMEOUT))
  while :; do  # no accounting daemon: done is an empty queue
    q=$(timeout 5 squeue -h -o '%i %T' 2>&1) || q="squeue failed: $q"
    [ -z "$q" ] && break
    if [ $SECONDS -ge $end ]; then echo "arrays not finished after ${SLURM_TIMEOUT}s:" >&2; echo "$q" >&2; exit 1; fi
    sleep 1
  done
  for id in $ids; do
    n=$(timeout 5 scontrol -o show job "$id" 2>/dev/null | grep -c 'JobState=COMPLETED')
    [ "$n" = 4 ] || { echo "job $id: $n of 4 array tasks COMPLETED" >&2; exit 1; }
  done
  exit 0
fi

BIN=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
BUILD=$(dirname "$BIN")
SRC=$(cd "$HERE/../.." && pwd)
WORK=$(mktemp -d "${TMPDIR:-/tmp}/sharded_runs_test.XXXXXX")
passed=0 failed=0 skipped=0
pass() { echo "PASS: $*"; passed=$((passed + 1)); }
fail() { echo "FAIL: $*"; failed=$((failed + 1)); }
skipt() { echo "SKIP: $*"; skipped=$((skipped + 1)); }
CHILD=""
forward() { trap "" TERM INT HUP; [ -n "$CHILD" ] && kill -TERM "$CHILD" 2>/dev/null && wait "$CHILD"; exit "$1"; }
trap 'forward 143' TERM; trap 'forward 130' INT; trap 'forward 129' HUP
background() { "$@" & CHILD=$!; wait "$CHILD"; local rc=$?; CHILD=""; return $rc; }

# The runs: 6 sweep points, 4 golden cases, the fog flythrough's 48 frames.
cat > "$WORK/args.sh" <<ARGS
SWEEP_ARGS="$BUILD/scenes/default.json --base $BUILD/profiles/desktop.json --axis antialiasing=none,msaa2,msaa4 --axis tile_size=32,64 --resolution 64x36 --frames 1 --warmup 0 --threads 1 --truth none"
GOLDEN_ARGS="--dir $SRC/tests/golden --only sky_*.mobile --resolution 320x180 --threads 2"
RENDER_ARGS="$BUILD/scenes/fog_valley_flythrough.json --resolution 160x90 --threads 1 --no-trace --quiet"
ARGS
. "$WORK/args.sh"
t0=$SECONDS

# (the sweep's shards share one folder of cached references: rendered once, locked)
# Compares a merged run with the unsharded one: sweep rows without their
# times, golden rows' verdicts and metrics.
same_json() {  # kind whole merged
  python3 - "$@" <<'PY'
import json, sys
kind, a, b = sys.argv[1:]
if kind == "sweep":
    strip = lambda r: {k: v for k, v in r.items() if k not in ("frame_ms_p50", "frame_ms_p95", "frame_ms_p99", "passes", "profile")}
    x, y = (json.load(open(p + "/sweep.json"))["points"] for p in (a, b))
else:
    strip = lambda r: {k: r[k] for k in ("case", "frame", "status", "metrics", "deterministic")}
    x, y = (json.load(open(p + "/golden_report.json"))["rows"] for p in (a, b))
ok = len(x) == len(y) > 0 and all(strip(r) == strip(s) for r, s in zip(x, y))
print(f"{kind}: {len(x)} unsharded rows, {len(y)} merged rows, {'equal' if ok else 'DIFFERENT'}")
sys.exit(0 if ok else 1)
PY
}

# shellcheck disable=SC2086  # the argument strings are split on purpose
"$BIN" sweep $SWEEP_ARGS --out "$WORK/whole/sweep" >/dev/null 2>&1 || fail "unsharded sweep"
"$BIN" golden $GOLDEN_ARGS --report "$WORK/whole/golden" >/dev/null 2>&1 || fail "unsharded golden check"

# shellcheck disable=SC2086
check_merge() {  # label folder-prefix
  local label=$1 pre=$2
  if "$BIN" merge "$pre/sweep".{0,1,2,3} --out "$pre/sweep.merged" >/dev/null 2>"$pre/merge.err" &&
     same_json sweep "$WORK/whole/sweep" "$pre/sweep.merged"; then pass "$label: 4-shard sweep merged equals the unsharded sweep"
  else fail "$label: sweep merge ($(tail -1 "$pre/merge.err"))"; fi
  if "$BIN" merge "$pre/golden".{0,1,2,3} --out "$pre/golden.merged" >/dev/null 2>"$pre/merge.err" &&
     same_json golden "$WORK/whole/golden" "$pre/golden.merged"; then pass "$label: 4-shard golden check merged equals the unsharded check"
  else fail "$label: golden merge ($(tail -1 "$pre/merge.err"))"; fi
}

# 1. GNU parallel, two jobs at a time.
if command -v parallel >/dev/null 2>&1; then
  P=$WORK/parallel; mkdir -p "$P"
  # shellcheck disable=SC2086
  if timeout 300 parallel --will-cite -j2 --halt now,fail=1 "$BIN" sweep $SWEEP_ARGS --shard {}/4 --references "$P/references" --out "$P/sweep.{}" ::: 0 1 2 3 </dev/null >/dev/null 2>&1 &&
     timeout 300 parallel --will-cite -j2 --halt now,fail=1 "$BIN" golden $GOLDEN_ARGS --shard {}/4 --report "$P/golden.{}" ::: 0 1 2 3 </dev/null >/dev/null 2>&1
  then check_merge "GNU parallel" "$P"
  else fail "GNU parallel: a shard failed"; fi
  # A merge of three shards is refused with the missing one named.
  msg=$("$BIN" merge "$P/sweep".{0,1,3} --out "$P/bad" 2>&1)
  if [ $? = 2 ] && echo "$msg" | grep -q "2/4 missing"; then pass "merge refuses 3 of 4 shards, naming the missing one"
  else fail "merge of 3 of 4 shards was not refused"; fi

  # 2. The fog flythrough in 4 blocks against the single-machine frames.
  # shellcheck disable=SC2086
  "$BIN" render $RENDER_ARGS --out "$WORK/whole/render" >/dev/null 2>&1 || fail "unsharded render"
  for warm in auto 24; do
    # shellcheck disable=SC2086
    if timeout 300 parallel --will-cite -j2 --halt now,fail=1 "$BIN" render $RENDER_ARGS --warmup-frames $warm --shard {}/4 --out "$P/render$warm.{}" ::: 0 1 2 3 </dev/null >/dev/null 2>&1 &&
       "$BIN" merge "$P/render$warm".{0,1,2,3} --out "$P/render$warm.merged" >/dev/null 2>&1; then
      identical=0 within=0 total=0
      for f in "$WORK/whole/render"/frame_*.png; do
        g="$P/render$warm.merged/$(basename "$f")"
        total=$((total + 1))
        if cmp -s "$f" "$g"; then identical=$((identical + 1)); within=$((within + 1))
        elif "$BIN" compare "$f" "$g" --max-abs 0.0040 --pixel-threshold 0.0040 --max-fraction 0 >/dev/null 2>&1; then
          within=$((within + 1)); fi
      done
      if [ $warm = auto ] && [ $total = 48 ] && [ $identical = 48 ]; then
        pass "4-shard fog flythrough, automatic warm-up: 48 of 48 frames bit-identical to the single-machine render"
      elif [ $warm = 24 ] && [ $total = 48 ] && [ $within = 48 ]; then
        pass "4-shard fog flythrough, 24-frame warm-up: $identical of 48 frames bit-identical, all within one 8-bit code"
      else fail "4-shard fog flythrough, warm-up $warm: $identical identical, $within within tolerance, of $total"; fi
    else fail "4-shard render (warm-up $warm) failed"; fi
  done
else
  skipt "GNU parallel: not installed (tests/setup_debian.sh)"
fi

# 3. Slurm job arrays on a one-node cluster started and stopped here.
CLUSTER=$WORK/cluster
background timeout -k 20 $((SLURM_TIMEOUT + 120)) "$HERE/slurm_cluster.sh" run "$CLUSTER" -- \
  "$HERE/sharded_runs_test.sh" --slurm "$WORK" "$BIN"
rc=$?
case $rc in
  0) check_merge "Slurm job arrays" "$WORK/slurm" ;;
  77) skipt "Slurm: the cluster cannot run here (reason above)" ;;
  *) fail "Slurm job arrays (exit $rc); logs under $CLUSTER/log and $WORK/slurm" ;;
esac

echo "sharded_runs_test: $((SECONDS - t0))s, $passed passed, $failed failed, $skipped skipped"
if [ $failed -gt 0 ]; then echo "kept $WORK for debugging" >&2; exit 1; fi
rm -rf "$WORK"
[ $skipped -gt 0 ] && exit 77
exit 0
