#!/usr/bin/env bash
# Tests the scale-out harness: a 4-task job array on a real one-node Slurm cluster started by
# slurm_cluster.sh, the same fan-out with GNU parallel, and that nothing of the cluster is left.
# Exit 0 pass, 77 skip (nothing failed but a part could not run here), 1 fail.
# SLURM_CLUSTER_STRICT=1 makes the harness's skips failures.
set -uo pipefail

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
HARNESS=$HERE/slurm_cluster.sh
ARRAY_TIMEOUT=${SLURM_TEST_ARRAY_TIMEOUT:-40}   # seconds for the whole array to finish

# --inside DIR: runs under `slurm_cluster.sh run`, with SLURM_CONF set.
if [ "${1:-}" = --inside ]; then
  out=$2/array
  mkdir -p "$out"
  jid=$(timeout 15 sbatch --parsable --array=0-3 --job-name=harness_array --chdir="$out" \
        --output="$out/slurm-%A_%a.out" \
        --wrap 'echo "$SLURM_ARRAY_TASK_ID" > "task_$SLURM_ARRAY_TASK_ID.txt"') \
    || { echo "sbatch failed" >&2; exit 1; }
  jid=${jid%%;*}
  echo "submitted array job $jid" >&2
  end=$((SECONDS + ARRAY_TIMEOUT))
  # No accounting here: completion is an empty queue, then the job records and the files.
  while :; do
    q=$(timeout 5 squeue -h -o '%i %T' 2>&1) || q="squeue failed: $q"
    [ -z "$q" ] && break
    if [ $SECONDS -ge $end ]; then
      echo "array not finished after ${ARRAY_TIMEOUT}s; queue:" >&2; echo "$q" >&2; exit 1
    fi
    sleep 0.5
  done
  states=$(timeout 5 scontrol -o show job "$jid" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | sort | uniq -c)
  echo "job records: $(echo "$states" | tr -s ' \n' ' ')" >&2
  fail=0
  [ "$(echo "$states" | awk '$2 == "JobState=COMPLETED" { print $1 }')" = 4 ] \
    || { echo "expected 4 COMPLETED array tasks" >&2; fail=1; }
  for i in 0 1 2 3; do
    got=$(cat "$out/task_$i.txt" 2>/dev/null)
    [ "$got" = "$i" ] || { echo "task_$i.txt: expected '$i', got '$got'" >&2; fail=1; }
  done
  exit $fail
fi

passed=0 failed=0 skipped=0
# Harness calls run in the background so that a signal to this script reaches them at once
# (timeout puts them in a process group of their own); `run` then stops its cluster.
CHILD=""
forward() { trap "" TERM INT HUP; [ -n "$CHILD" ] && kill -TERM "$CHILD" 2>/dev/null && wait "$CHILD"; exit "$1"; }
trap 'forward 143' TERM; trap 'forward 130' INT; trap 'forward 129' HUP
harness() { "$@" & CHILD=$!; wait "$CHILD"; local rc=$?; CHILD=""; return $rc; }
pass() { echo "PASS: $*"; passed=$((passed + 1)); }
fail() { echo "FAIL: $*"; failed=$((failed + 1)); }
skipt() { echo "SKIP: $*"; skipped=$((skipped + 1)); }

WORK=$(mktemp -d "${TMPDIR:-/tmp}/slurm_cluster_test.XXXXXX")
t0=$SECONDS

# 1. GNU parallel: the same four tasks, two at a time.
if command -v parallel >/dev/null 2>&1; then
  mkdir -p "$WORK/parallel"
  if timeout 30 parallel --will-cite -j2 "echo {} > '$WORK/parallel/task_{}.txt'" ::: 0 1 2 3 </dev/null; then
    ok=1
    for i in 0 1 2 3; do [ "$(cat "$WORK/parallel/task_$i.txt" 2>/dev/null)" = "$i" ] || ok=0; done
    if [ $ok = 1 ]; then pass "GNU parallel -j2 ran 4 tasks"; else fail "GNU parallel outputs wrong"; fi
  else
    fail "GNU parallel exited non-zero"
  fi
else
  skipt "GNU parallel: parallel not installed (tests/setup_debian.sh)"
fi

# 2. Slurm job array on a cluster started and stopped by `run`.
CLUSTER=$WORK/cluster
harness timeout -k 20 150 "$HARNESS" run "$CLUSTER" -- "$HERE/slurm_cluster_test.sh" --inside "$CLUSTER"
rc=$?
case $rc in
  0) pass "Slurm job array of 4 tasks" ;;
  77) skipt "Slurm job array: cluster cannot run here (reason above)" ;;
  *) fail "Slurm job array (exit $rc); logs under $CLUSTER/log" ;;
esac

if [ $rc != 77 ]; then
  # 3. Nothing of this cluster is left running (zombies awaiting reaping do not count).
  # (the watchdog of `run` may take up to a second to notice it is done)
  end=$((SECONDS + 5))
  while :; do
    left=$(ps -eo pid=,stat=,args= | D=$CLUSTER awk 'index($0, ENVIRON["D"]) && $2 !~ /^Z/')
    for p in $(pgrep -x slurmstepd); do
      [ -n "$(find "/proc/$p/fd" -lname "$CLUSTER/*" 2>/dev/null)" ] && left+=" slurmstepd $p"
    done
    [ -z "$left" ] || [ $SECONDS -ge $end ] && break
    sleep 0.5
  done
  if [ -z "$left" ]; then pass "no daemon of the cluster left after run"; else fail "left running: $left"; fi

  # 4. Exit status propagation and restart in the same directory; stop is idempotent.
  harness timeout -k 20 120 "$HARNESS" run "$CLUSTER" -- sh -c 'sinfo -h -o %T | grep -qx idle && exit 3'
  rc2=$?
  if [ $rc2 = 3 ]; then pass "run restarts in the same DIR and propagates the exit status (3)"
  else fail "run propagated $rc2, expected 3"; fi
  if "$HARNESS" stop "$CLUSTER" 2>/dev/null; then pass "stop after run is a no-op"; else fail "second stop failed"; fi
fi

echo "slurm_cluster_test: $((SECONDS - t0))s"
echo "$passed passed, $failed failed, $skipped skipped"
if [ $failed -gt 0 ]; then echo "kept $WORK for debugging" >&2; exit 1; fi
rm -rf "$WORK"
[ $skipped -gt 0 ] && exit 77
exit 0
