#!/usr/bin/env bash
# Installs the Debian packages eulersplat needs (only those missing), then
# configures and builds into build/. Idempotent: re-running only rebuilds.
set -euo pipefail
case "${1:-}" in
  -h|--help) sed -n '2,3p' "$0"; echo "usage: scripts/setup.sh"; exit 0 ;;
  "") ;;
  *) echo "setup.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
esac
cd "$(dirname "$0")/.."

PACKAGES=(cmake g++ make pkg-config libceres-dev libeigen3-dev libopencv-dev
          libopencv-contrib-dev libgoogle-glog-dev libgflags-dev libgtest-dev
          libgmock-dev libbenchmark-dev nlohmann-json3-dev colmap ffmpeg
          chromium libopenmpi-dev openmpi-bin)
# node and npm run the web page's viewer install and the tests that drive a
# browser or check our files with other splat tools; a node from elsewhere
# (with its own npm) is used as it is.
command -v npm > /dev/null || PACKAGES+=(nodejs npm)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" \
    || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "[setup] installing: ${missing[*]}"
  SUDO=""; [[ $(id -u) -ne 0 ]] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# The Gaussian-splat viewer es_export copies next to its web page, and the
# test drivers, from the npm registry at the versions web/package-lock.json
# pins (no install scripts: nothing but the packages is downloaded).
if [[ ! -f web/node_modules/.package-lock.json ||
      web/package-lock.json -nt web/node_modules/.package-lock.json ]]; then
  echo "[setup] installing npm packages into web/node_modules"
  (cd web && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error)
fi

jobs=$(nproc)
# ccache, when installed, makes rebuilds after a checkout switch cheap.
launcher=()
command -v ccache > /dev/null &&
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_CUDA_COMPILER_LAUNCHER=ccache)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" > build.log 2>&1 || { cat build.log; exit 1; }
echo "[setup] building with $jobs jobs (log: build.log)"
if ! cmake --build build -j"$jobs" >> build.log 2>&1; then
  grep -E -B2 -A6 "error" build.log | head -80
  echo "[setup] build failed; see build.log"; exit 1
fi
echo "[setup] built into build/bin"
