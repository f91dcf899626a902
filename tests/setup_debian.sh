#!/usr/bin/env bash
# Installs the Debian packages the project needs (only those missing).
set -euo pipefail
packages=(build-essential cmake libglm-dev libtinygltf-dev libstb-dev libopenexr-dev doctest-dev
          nlohmann-json3-dev assimp-testmodels libdraco-dev libmeshoptimizer-dev libpng-dev libjpeg62-turbo-dev
          clang libclang-rt-14-dev python3-matplotlib chromium
          slurm-wlm munge parallel)  # the last three: tests/scaleout (a throwaway one-node Slurm cluster)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
fi
