#!/usr/bin/env bash
# mobile_vs_desktop.sh: the mobile profile's error against desktop at the same resolution, and both
# profiles' frame times, per shipped scene.
#
# A benchmark, not a test: not part of CI; it prints a table (and writes OUT/table.md).
#
# For each scene in scenes/*.json: render FRAMES frames (the scene's own count when smaller) with
# profiles/desktop.json and profiles/mobile.json, both at the mobile resolution (960x540) and with
# the same thread count, and compare the last frame with `cpurender compare`: mean and p95 relative
# luminance error (sRGB-decoded PNGs, pixels darker than 1% of the mean measured against that
# floor) and mean LDR-FLIP. Frame times are the reports' p50 and p95 over the frames (the first
# frame, which bakes every LUT and the static shadow map, is the p95 of short runs).
#
# usage: tests/bench/mobile_vs_desktop.sh [--build DIR] [--frames N] [--threads N] [--out DIR] [SCENE...]
set -euo pipefail
cd "$(dirname "$0")/../.."
build=build frames=8 threads=1 out=out/mobile_vs_desktop
scenes=()
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    -h|--help) sed -n '2,14p' "$0"; exit 0 ;;
    *) scenes+=("$1"); shift ;;
  esac
done
[ ${#scenes[@]} -gt 0 ] || scenes=(scenes/*.json)
exe="$build/cpurender"
mkdir -p "$out"
table="$out/table.md"
printf '| scene | frames | rel. lum. error mean | p95 | FLIP mean | desktop ms p50 / p95 | mobile ms p50 / p95 |\n' > "$table"
printf '|---|---:|---:|---:|---:|---:|---:|\n' >> "$table"
for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .json)
  n=$(python3 -c "import json,sys; print(min($frames, json.load(open('$scene')).get('frames', 1)))")
  for profile in desktop mobile; do
    "$exe" render "$scene" --profile "profiles/$profile.json" --resolution 960x540 --frames "$n" \
      --threads "$threads" --out "$out/$name.$profile" --quiet --no-trace
  done
  last=$(printf 'frame_%04d.png' $((n - 1)))
  "$exe" compare "$out/$name.desktop/$last" "$out/$name.mobile/$last" --json "$out/$name.compare.json" \
    > /dev/null || true
  python3 - "$out" "$name" "$n" >> "$table" <<'PY'
import json, sys
out, name, n = sys.argv[1], sys.argv[2], sys.argv[3]
m = json.load(open(f"{out}/{name}.compare.json"))["metrics"]
def times(profile):
    f = json.load(open(f"{out}/{name}.{profile}/report.json"))["summary"]["frame_ms"]
    return f"{f['p50']:.1f} / {f['p95']:.1f}"
print(f"| {name} | {n} | {100 * m['rel_luminance_mean']:.2f}% | {100 * m['rel_luminance_p95']:.2f}% | "
      f"{m['flip_mean']:.4f} | {times('desktop')} | {times('mobile')} |")
PY
done
cat "$table"
