#!/usr/bin/env bash
# Fingerprints of every frame a build renders: each shipped scene under each
# shipped profile, the anti-aliasing golden cases and (with CR_ASSETS_DIR) the
# model golden cases, at the golden size (320x180, frames 0..8) and the
# default scene at 1280x720, each with 1 and 2 threads, as PNG and EXR. Two
# builds' lists are equal exactly when their frames are byte-identical:
#   tests/frame_hashes.sh build/cpurender > before.txt   # (old build)
#   tests/frame_hashes.sh build/cpurender > after.txt    # (new build)
#   diff before.txt after.txt && wc -l after.txt
# A refactoring that must not change behaviour proves it this way.
set -euo pipefail
bin=$(realpath "${1:?usage: frame_hashes.sh CPURENDER}")
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

render() {  # label, scene, profile, resolution, frames, threads
  local out="$work/$1.$6t"
  "$bin" render "$2" --profile "$3" --resolution "$4" --frames "$5" --threads "$6" --format png,exr \
    --no-trace --quiet --out "$out" >/dev/null
  (cd "$out" && sha256sum frame_*) | sed "s|^|$1 $6t |"
}

cases=()
for s in "$root"/scenes/*.json; do
  for p in "$root"/profiles/*.json; do cases+=("$(basename "$s" .json).$(basename "$p" .json)|$s|$p"); done
done
for p in "$root"/tests/golden/antialiasing/profiles/*.json; do
  cases+=("aa.$(basename "$p" .json)|$root/tests/golden/antialiasing/scenes/default.json|$p")
done
if [ -n "${CR_ASSETS_DIR:-}" ] && [ -d "$CR_ASSETS_DIR/khronos" ]; then
  for s in "$root"/tests/golden/models/scenes/*.json; do
    cases+=("model.$(basename "$s" .json)|$s|$root/profiles/desktop.json")
  done
fi
for c in "${cases[@]}"; do
  IFS='|' read -r label scene profile <<<"$c"
  for t in 1 2; do render "$label" "$scene" "$profile" 320x180 9 "$t"; done
done
for t in 1 2; do render "default.1280x720" "$root/scenes/default.json" "$root/profiles/desktop.json" 1280x720 2 "$t"; done
