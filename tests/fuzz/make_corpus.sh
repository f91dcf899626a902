#!/usr/bin/env bash
# Builds the fuzz targets' seed corpora (docs/fuzzing.md) from the project's
# inputs and Debian's assimp-testmodels:
#   tests/fuzz/make_corpus.sh OUT_DIR [FUZZ_BUILD_DIR]
# writes OUT_DIR/{gltf,scene,profile,image}/, replacing what was there.
#   gltf     tests/data/bad/*.gltf|glb, /usr/share/assimp/models/glTF2/**,
#            the generated default.glb (build/scenes/, else FUZZ_BUILD_DIR's
#            release sibling; $CR_DEFAULT_GLB names another) and, with
#            $CR_ASSETS_DIR, its models up to 1 MiB. External buffers and
#            images are inlined as data URIs (cr_fuzz_corpus_tool), since a
#            target sees only its own bytes.
#   scene    scenes/*.json, tests/golden/**/scenes/*.json, tests/data/bad/{scene,fuzz_scene}_*;
#            "gltf" is pointed at default.glb, which the scene target provides.
#   profile  profiles/*.json, tests/golden/**/profiles/*.json, tests/data/bad/{profile,fuzz_profile}_*.
#   image    small generated PNGs and JPEGs (cr_fuzz_corpus_tool images), and
#            the PNG and JPEG files of tests/, assimp-testmodels and
#            $CR_ASSETS_DIR up to 64 KiB (larger images decode too slowly to fuzz well).
# FUZZ_BUILD_DIR (default build-fuzz) holds cr_fuzz_corpus_tool.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
out=${1:?usage: make_corpus.sh OUT_DIR [FUZZ_BUILD_DIR]}
build=${2:-$root/build-fuzz}
tool=$build/tests/fuzz/cr_fuzz_corpus_tool
assimp=/usr/share/assimp/models/glTF2
[ -x "$tool" ] || { echo "make_corpus.sh: $tool missing (build the fuzz_targets target)" >&2; exit 1; }
[ -d "$assimp" ] || echo "make_corpus.sh: warning: $assimp missing (apt-get install assimp-testmodels)" >&2

rm -rf "$out/gltf" "$out/scene" "$out/profile" "$out/image"
mkdir -p "$out/gltf" "$out/scene" "$out/profile" "$out/image"

# A readable, unique seed name: the source path relative to its root, '/' -> '_'.
name_of() { local rel=${1#"$2"/}; echo "${3}${rel//\//_}"; }

add_gltf() {  # file, root, prefix
  local dest
  dest=$out/gltf/$(name_of "$1" "$2" "$3")
  case "$1" in
    *.gltf) "$tool" inline "$1" "$dest" ;;
    *) cp "$1" "$dest" ;;
  esac
}

for f in "$root"/tests/data/bad/*.gltf "$root"/tests/data/bad/*.glb; do
  [ -f "$f" ] && add_gltf "$f" "$root/tests/data/bad" bad_
done
if [ -d "$assimp" ]; then
  while IFS= read -r -d '' f; do add_gltf "$f" "$assimp" assimp_; done \
    < <(find "$assimp" -type f \( -name '*.gltf' -o -name '*.glb' \) -print0 | sort -z)
fi
default_glb=${CR_DEFAULT_GLB:-}
if [ -z "$default_glb" ]; then
  for d in "$root/build/scenes/default.glb" "$build/scenes/default.glb"; do
    [ -f "$d" ] && { default_glb=$d; break; }
  done
fi
if [ -n "$default_glb" ] && [ -f "$default_glb" ]; then
  cp "$default_glb" "$out/gltf/generated_default.glb"
else
  echo "make_corpus.sh: warning: no generated default.glb (build the scene_assets target)" >&2
fi
if [ -n "${CR_ASSETS_DIR:-}" ] && [ -d "$CR_ASSETS_DIR" ]; then
  while IFS= read -r -d '' f; do
    add_gltf "$f" "$CR_ASSETS_DIR" assets_
    dest=$out/gltf/$(name_of "$f" "$CR_ASSETS_DIR" assets_)
    [ "$(stat -c %s "$dest")" -le 1048576 ] || rm -f "$dest"
  done < <(find "$CR_ASSETS_DIR" -type f \( -name '*.gltf' -o -name '*.glb' \) -size -1025k -print0 | sort -z)
fi

# Scene files: the "gltf" value becomes default.glb (present in the target's
# scratch folder), so the keys after it are read too; the bad ones also go in
# as they are.
for f in "$root"/scenes/*.json "$root"/tests/golden/*/scenes/*.json "$root"/tests/golden/models/scenes/*.json \
         "$root"/tests/data/bad/scene_*.json "$root"/tests/data/bad/fuzz_scene_*; do
  [ -f "$f" ] || continue
  dest=$out/scene/$(name_of "$f" "$root" "")
  sed -E 's/"gltf"[[:space:]]*:[[:space:]]*"[^"]*"/"gltf": "default.glb"/' "$f" > "$dest"
  case "$f" in */bad/*) cp "$f" "$dest.orig.json" ;; esac
done

for f in "$root"/profiles/*.json "$root"/tests/golden/*/profiles/*.json "$root"/tests/data/bad/profile_*.json \
         "$root"/tests/data/bad/fuzz_profile_*; do
  [ -f "$f" ] && cp "$f" "$out/profile/$(name_of "$f" "$root" "")"
done

add_images() {  # dir, prefix
  while IFS= read -r -d '' f; do cp "$f" "$out/image/$(name_of "$f" "$1" "$2")"; done \
    < <(find "$1" -type f \( -iname '*.png' -o -iname '*.jpg' -o -iname '*.jpeg' \) -size -65k -print0 | sort -z)
}
"$tool" images "$out/image"
add_images "$root/tests" tests_
[ -d "$assimp" ] && add_images "$assimp" assimp_
[ -n "${CR_ASSETS_DIR:-}" ] && [ -d "$CR_ASSETS_DIR" ] && add_images "$CR_ASSETS_DIR" assets_

for k in gltf scene profile image; do
  echo "$k: $(find "$out/$k" -type f | wc -l) seeds, $(du -sh "$out/$k" | cut -f1)"
done
