#!/usr/bin/env bash
# llvmpipe_compare.sh: cpurender against Mesa llvmpipe on equal work.
#
# A benchmark, not a test: it is not part of CI and checks nothing; it prints timings.
#
# For each model it renders the same frame with cpurender and with the llvmpipe peer
# (../shared/tools/llvmpipe-peer: Mesa llvmpipe through OSMesa, a fixed shading model) and
# prints the median frame times and the ratio llvmpipe / cpurender (above 1: cpurender is faster).
#
# Equal work, as the peer's README defines it:
#   - the glTF is stripped to what the peer shades (strip_gltf.py: base-colour texture and factors,
#     metallic/roughness factors; no normal, occlusion, emissive or metal-rough textures, no
#     material extensions);
#   - cpurender renders it with a temporary copy of profiles/desktop.json that sets
#     "shadow_map_size": 0 and "antialiasing": "none", from a scene file with no plugin sections;
#   - both render 1280x720 (W, H) with the same camera: cpurender's `--camera auto` three-quarter
#     view (vertical fov 40 deg, azimuth 35 deg, elevation 15 deg, bounding sphere fitted with a 5%
#     margin, near = (distance - radius) / 2), computed here from the peer's BBOX line and given to
#     the peer as --eye/--target/--fov/--near and to cpurender as the scene file's explicit camera
#     (so a model's own glTF camera is not used by either);
#   - the same sun direction (cpurender's default when the scene has none: elevation 75, azimuth 45),
#     passed to the peer with --sun.
# Timed on both sides: the frame only (not loading, texture decode, JIT warm-up); FRAMES timed
# frames after 2 warm-up frames, median per run.
# Threads: cpurender `bench --threads 2` runs 1 thread then 2 threads; the peer runs with
# LP_NUM_THREADS=0 (everything on one thread) and LP_NUM_THREADS=2 (application thread + 2 raster
# threads on the 2 cores). Runs are interleaved: every round runs every model on both renderers,
# the order of the two renderers alternating between rounds. A cell is the median of the per-round
# medians.
#
# Usage:
#   tests/bench/llvmpipe_compare.sh [--peer PEER] [--rounds N] [--frames N] [MODEL.gltf|.glb ...]
#
# Models: 2CylinderEngine (assimp-testmodels), DamagedHelmet and FlightHelmet from
# $CR_ASSETS_DIR (default ../shared/assets), the 512x512 grid from make_grid.py, then any models
# given on the command line.
#
# Environment (options win):
#   PEER           peer binary; default: ../shared/tools/llvmpipe-peer built by its build.sh into a
#                  temporary folder (needs the Debian packages its README lists)
#   PEER_DIR       the peer's folder (default ../shared/tools/llvmpipe-peer): strip_gltf.py, make_grid.py
#   CPURENDER      cpurender binary (default build/cpurender, release build)
#   CR_ASSETS_DIR  shared assets (default ../shared/assets)
#   ROUNDS         rounds (default 5);  FRAMES  timed frames per run (default 20)
#   W, H           resolution (default 1280x720)
#   KEEP=1         keep the temporary folder (stripped models, profile, scene files, raw results)
#
# Output: progress on stderr, then a markdown table (model, triangles, cpurender and llvmpipe medians
# at 1 and 2 threads, ratio llvmpipe / ours), cpurender's per-pass medians, and a note for every
# peer run that saw other processes using the CPU (other_load > 0.05: rerun on a quiet machine).
set -euo pipefail

REPO=$(cd "$(dirname "$0")/../.." && pwd)
PEER_DIR=${PEER_DIR:-$REPO/../shared/tools/llvmpipe-peer}
CPURENDER=${CPURENDER:-$REPO/build/cpurender}
CR_ASSETS_DIR=${CR_ASSETS_DIR:-$REPO/../shared/assets}
ROUNDS=${ROUNDS:-5}
FRAMES=${FRAMES:-20}
W=${W:-1280}
H=${H:-720}
PEER=${PEER:-}
EXTRA=()

usage() { sed -n '/^# Usage:/,/^# Output:/p' "$0" | sed 's/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
  case "$1" in
    --peer) PEER=$2; shift 2 ;;
    --rounds) ROUNDS=$2; shift 2 ;;
    --frames) FRAMES=$2; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    -*) echo "llvmpipe_compare.sh: unknown option $1" >&2; usage >&2; exit 1 ;;
    *) EXTRA+=("$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"); shift ;;
  esac
done

WORK=$(mktemp -d /tmp/llvmpipe_compare.XXXXXX)
if [ "${KEEP:-0}" = 1 ]; then echo "keeping $WORK" >&2; else trap 'rm -rf "$WORK"' EXIT; fi

[ -x "$CPURENDER" ] || { echo "no cpurender binary at $CPURENDER (build a release build first)" >&2; exit 1; }
if [ -z "$PEER" ]; then
  echo "building the peer into $WORK/peer-src ..." >&2
  cp -r "$PEER_DIR" "$WORK/peer-src"
  "$WORK/peer-src/build.sh" >&2
  PEER=$WORK/peer-src/peer
fi
[ -x "$PEER" ] || { echo "no peer binary at $PEER" >&2; exit 1; }

# Equal-work profile: the desktop profile without shadow map and anti-aliasing.
python3 - "$REPO/profiles/desktop.json" "$WORK/profile.json" <<'EOF'
import json, sys
p = json.load(open(sys.argv[1]))
p["name"] = "llvmpipe-equal-work"
p["shadow_map_size"] = 0
p["antialiasing"] = "none"
json.dump(p, open(sys.argv[2], "w"), indent=1)
EOF

python3 "$PEER_DIR/make_grid.py" "$WORK/grid.glb" 512 >/dev/null
MODELS=("/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"
        "$CR_ASSETS_DIR/DamagedHelmet/glTF-Binary/DamagedHelmet.glb"
        "$CR_ASSETS_DIR/FlightHelmet/glTF/FlightHelmet.gltf"
        "$WORK/grid.glb")
MODELS+=("${EXTRA[@]}")

# cpurender's default sun when the scene has none: elevation 75, azimuth 45 (clockwise from +Z to +X).
SUN=$(python3 -c 'import math; az, el = math.radians(45), math.radians(75)
print("%.9g,%.9g,%.9g" % (math.sin(az)*math.cos(el), math.sin(el), math.cos(az)*math.cos(el)))')

NAMES=()
for src in "${MODELS[@]}"; do
  if [ ! -f "$src" ]; then echo "note: $src absent, skipped" >&2; continue; fi
  base=$(basename "$src"); name=${base%.*}
  d="$WORK/m_$name"; mkdir -p "$d"
  python3 "$PEER_DIR/strip_gltf.py" "$src" "$d/$base" >/dev/null
  # strip_gltf.py makes a .gltf's file URIs absolute; tinygltf 2.7 (in both renderers) prefixes the
  # model's folder even to absolute URIs, so make them relative to the stripped copy's folder.
  case "$base" in *.gltf) python3 - "$d/$base" <<'EOF'
import json, os, sys
p = sys.argv[1]; j = json.load(open(p))
for coll in ("buffers", "images"):
    for x in j.get(coll, []):
        if os.path.isabs(x.get("uri", "")): x["uri"] = os.path.relpath(x["uri"], os.path.dirname(p))
json.dump(j, open(p, "w"))
EOF
  esac
  # The peer's BBOX line is the world-space box of the drawn vertices (cpurender frames the same box).
  # The peer runs in the model's folder with a bare file name: tinygltf 2.7 prefixes the folder even
  # to the absolute URIs strip_gltf.py writes into a stripped .gltf.
  echo "$base" > "$d/model"
  bbox=$(cd "$d" && GALLIUM_DRIVER=llvmpipe LP_NUM_THREADS=0 "$PEER" --gltf "$base" --width "$W" --height "$H" \
           --frames 1 --warmup 0 --out "$d/peer.png" 2>&1 | grep '^BBOX') || {
    echo "peer failed on $d/$base:" >&2
    (cd "$d" && "$PEER" --gltf "$base" --frames 1 --warmup 0 --out "$d/peer.png" 2>&1 | grep -v '^GL' >&2); exit 1; }
  python3 - "$bbox" "$W" "$H" "$base" "$d" <<'EOF'
import json, math, re, sys
bbox, w, h, base, d = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4], sys.argv[5]
m = re.search(r"min=(\S+) max=(\S+)", bbox)
lo = [float(v) for v in m.group(1).split(",")]; hi = [float(v) for v in m.group(2).split(",")]
# cpurender's three_quarter_view (engine/render/frame_view.cpp).
c = [0.5 * (a + b) for a, b in zip(lo, hi)]
radius = max(1e-3, 0.5 * math.dist(lo, hi))
vfov = math.radians(40.0); aspect = w / h
half = min(0.5 * vfov, math.atan(math.tan(0.5 * vfov) * aspect))
dist = radius / math.sin(half) * 1.05
az, el = math.radians(35.0), math.radians(15.0)
dv = (math.sin(az) * math.cos(el), math.sin(el), math.cos(az) * math.cos(el))
eye = [ci + di * dist for ci, di in zip(c, dv)]
znear = max(1e-4, (dist - radius) * 0.5)
json.dump({"gltf": base, "camera": {"position": eye, "target": c, "vfov_deg": 40, "znear": znear}, "frames": 1},
          open(f"{d}/scene.json", "w"), indent=1)
f = lambda v: ",".join("%.9g" % x for x in v)
open(f"{d}/peer_camera", "w").write(f"--eye {f(eye)} --target {f(c)} --up 0,1,0 --fov 40 --near {znear:.9g}\n")
EOF
  NAMES+=("$name")
done

RESULTS="$WORK/results.tsv"; : > "$RESULTS"
run_cpurender() {  # name round
  local d="$WORK/m_$1"
  "$CPURENDER" bench "$d/scene.json" --no-default --profile "$WORK/profile.json" --resolution "${W}x$H" \
    --threads 2 --frames "$FRAMES" --warmup 2 --allow-missing-images --allow-outside-paths \
    --json "$d/cr_$2.json" >/dev/null 2>"$d/cr_$2.err" || { cat "$d/cr_$2.err" >&2; exit 1; }
  printf '%s\tcr\t%s\t%s\n' "$1" "$2" "$d/cr_$2.json" >> "$RESULTS"
}
run_peer() {  # name round
  local d="$WORK/m_$1" t line
  for t in 0 2; do
    # shellcheck disable=SC2046
    line=$(cd "$d" && GALLIUM_DRIVER=llvmpipe LP_NUM_THREADS=$t "$PEER" --gltf "$(cat "$d/model")" \
             --width "$W" --height "$H" --frames $((FRAMES + 2)) --warmup 2 --sun "$SUN" \
             $(cat "$d/peer_camera") --out "$d/peer_lp$t.png" 2>/dev/null | grep '^RESULT')
    printf '%s\tlp%s\t%s\t%s\n' "$1" "$t" "$2" "$line" >> "$RESULTS"
  done
}
for r in $(seq 1 "$ROUNDS"); do
  echo "round $r/$ROUNDS" >&2
  for name in "${NAMES[@]}"; do
    if [ $((r % 2)) = 1 ]; then run_cpurender "$name" "$r"; run_peer "$name" "$r"
    else run_peer "$name" "$r"; run_cpurender "$name" "$r"; fi
  done
done

python3 - "$RESULTS" "$ROUNDS" "$FRAMES" "$W" "$H" <<'EOF'
import json, statistics as st, sys
rows, names = {}, []
for ln in open(sys.argv[1]):
    name, kind, rnd, val = ln.rstrip("\n").split("\t")
    if name not in names: names.append(name)
    r = rows.setdefault(name, {"cr": [], "lp0": [], "lp2": []})
    if kind == "cr":
        r["cr"].append(json.load(open(val))[0])
    else:
        kv = dict(x.split("=", 1) for x in val.split()[1:])
        if float(kv.get("other_load", 0)) > 0.05:
            print(f"note: {name} LP_NUM_THREADS={kind[2:]} round {rnd}: other_load={kv['other_load']} (disturbed)")
        r[kind].append(kv)
med = lambda xs: st.median(xs)
print(f"\n{sys.argv[2]} rounds x {sys.argv[3]} timed frames, {sys.argv[4]}x{sys.argv[5]}; "
      "ms = median of per-round medians; ratio = llvmpipe / cpurender (above 1: cpurender is faster)\n")
print("| model | triangles | cpurender 1t ms | llvmpipe LP=0 ms | ratio 1t | cpurender 2t ms | llvmpipe LP=2 ms | ratio 2t |")
print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
passes, spread = {}, []
rng = lambda xs: f"{min(xs):.1f}-{max(xs):.1f}"
for n in names:
    r = rows[n]
    c1 = med([b["runs"][0]["frame_ms_median"] for b in r["cr"]])
    c2 = med([b["runs"][1]["frame_ms_median"] for b in r["cr"]])
    l0 = med([float(k["median_ms"]) for k in r["lp0"]])
    l2 = med([float(k["median_ms"]) for k in r["lp2"]])
    tris_cr, tris_lp = r["cr"][0]["triangles"], int(r["lp0"][0]["tris"])
    tris = f"{tris_lp:,}" if tris_cr == tris_lp else f"{tris_lp:,} (ours {tris_cr:,})"
    print(f"| {n} | {tris} | {c1:.2f} | {l0:.2f} | {l0 / c1:.2f}x | {c2:.2f} | {l2:.2f} | {l2 / c2:.2f}x |")
    passes[n] = r
    spread.append(f"{n}: cpurender 1t {rng([b['runs'][0]['frame_ms_median'] for b in r['cr']])}, "
                  f"2t {rng([b['runs'][1]['frame_ms_median'] for b in r['cr']])}; llvmpipe LP=0 "
                  f"{rng([float(k['median_ms']) for k in r['lp0']])}, LP=2 {rng([float(k['median_ms']) for k in r['lp2']])}")
print("\nrange of the per-round medians (ms):")
for line in spread: print("  " + line)
print("\ncpurender per pass (ms, median of per-round medians; 1 thread / 2 threads), pixels: cpurender's "
      "pixels shaded / llvmpipe's covered pixels\n")
print("| model | pass medians 1 thread | pass medians 2 threads | pixels shaded / covered |")
print("| --- | --- | --- | --- |")
for n, r in passes.items():
    cells = []
    for i in (0, 1):
        names_p = r["cr"][0]["runs"][i]["passes"].keys()
        cells.append(", ".join(f"{p} {med([b['runs'][i]['passes'][p]['median_ms'] for b in r['cr']]):.2f}"
                               for p in names_p))
    px = f"{r['cr'][0]['runs'][0]['pixels_shaded']:,} / {int(r['lp0'][0]['covered_px']):,}"
    print(f"| {n} | {cells[0]} | {cells[1]} | {px} |")
EOF
