#!/usr/bin/env bash
# Installs the Debian 12 packages the project needs (when missing), then configures and builds
# Release into build/. Idempotent; run as root or with sudo available.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake pkg-config
  libassimp-dev libeigen3-dev coinor-libclp-dev libfmt-dev libcli11-dev libgtest-dev
  nlohmann-json3-dev libstb-dev libsuitesparse-dev
  libopenblas0-pthread   # BLAS for CHOLMOD's supernodal factorization: 2-3x the reference BLAS
  leocad xvfb xauth   # real clients for rendering tests
  assimp-testmodels   # real meshes (textured, several objects) for legolize's tests
  chromium            # opens the instructions booklet in tests (headless)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}" >&2
  sudo_cmd=()
  [[ $(id -u) -eq 0 ]] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
