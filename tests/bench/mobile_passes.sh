#!/usr/bin/env bash
# mobile_passes.sh: per-pass times of the mobile profile against desktop at the same resolution (what
# precision and smaller LUTs buy), and of mobile at its own resolution, at 1 and 2 threads.
#
# A benchmark, not a test: not part of CI; it prints a Markdown table.
#
# Runs `cpurender bench` (N measured frames after 2 warm-up frames, per-pass medians) for each scene
# under desktop and mobile at 960x540 (the mobile resolution), ROUNDS times, the two profiles
# interleaved (their order alternating between rounds); a cell is the median of the rounds' medians.
# Columns: desktop and mobile at 1 thread, their ratio (mobile / desktop), the same at 2 threads.
#
# usage: tests/bench/mobile_passes.sh [--build DIR] [--rounds N] [--frames N] [--out DIR] [SCENE...]
#        (default scenes: scenes/default_flythrough.json scenes/fog_valley_flythrough.json)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=build rounds=3 frames=12 out=out/mobile_passes
scenes=()
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    -h|--help) sed -n '2,13p' "$0"; exit 0 ;;
    *) scenes+=("$1"); shift ;;
  esac
done
[ ${#scenes[@]} -gt 0 ] || scenes=(scenes/default_flythrough.json scenes/fog_valley_flythrough.json)
mkdir -p "$out"
for ((r = 0; r < rounds; ++r)); do
  order=(desktop mobile)
  [ $((r % 2)) -eq 1 ] && order=(mobile desktop)
  for profile in "${order[@]}"; do
    "$build/cpurender" bench "${scenes[@]}" --no-default --profile "profiles/$profile.json" --resolution 960x540 \
      --frames "$frames" --warmup 2 --threads 2 --json "$out/$profile.$r.json" > /dev/null
  done
done
python3 - "$out" "$rounds" <<'PY'
import json, statistics, sys
out, rounds = sys.argv[1], int(sys.argv[2])
runs = {p: [json.load(open(f"{out}/{p}.{r}.json")) for r in range(rounds)] for p in ("desktop", "mobile")}
for s, scene in enumerate(runs["desktop"][0]):
    name = scene.get("name") or scene.get("scene") or f"scene {s}"
    print(f"\n{name} at 960x540 (median of {rounds} rounds, ms)\n")
    print("| pass | desktop 1T | mobile 1T | mobile/desktop | desktop 2T | mobile 2T | mobile/desktop |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    def cell(profile, threads, key):
        values = []
        for rnd in runs[profile]:
            run = next(x for x in rnd[s]["runs"] if x["threads"] == threads)
            v = run["frame_ms_median"] if key == "frame" else run["passes"].get(key, {}).get("median_ms")
            if v is not None: values.append(v)
        return statistics.median(values) if values else None
    keys = sorted(set(runs["desktop"][0][s]["runs"][0]["passes"]) | set(runs["mobile"][0][s]["runs"][0]["passes"]))
    for key in keys + ["frame"]:
        row = [key if key != "frame" else "**frame**"]
        for threads in (1, 2):
            d, m = cell("desktop", threads, key), cell("mobile", threads, key)
            row += [f"{d:.2f}" if d is not None else "-", f"{m:.2f}" if m is not None else "-",
                    f"{m / d:.2f}" if d and m is not None else "-"]
        print("| " + " | ".join(row) + " |")
PY
