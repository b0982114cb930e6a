#!/usr/bin/env bash
# Installs what Lambert builds and tests with, if any of it is missing: the Debian 12 packages
# (apt-get; sudo when not root), and the npm packages into tools/node_modules, exactly as pinned by
# tools/package-lock.json: three.js (compiled into the binary for the browser viewer), the contract
# and export validators, and playwright-core, which drives Debian's chromium in tests/viewer_test.mjs
# (it downloads no browser). clang 14 with its sanitizer and libFuzzer runtimes (libclang-rt-14-dev)
# and llvm-symbolizer (llvm) build and run .ci/run's instrumented build and fuzz targets.
set -euo pipefail
cd "$(dirname "$0")/.."
packages=(build-essential cmake ninja-build pkg-config
          libcgal-dev libopenmesh-dev libembree-dev libcpp-httplib-dev nlohmann-json3-dev
          libcli11-dev libcairo2-dev fonts-dejavu-core libpng-dev libgtest-dev libbenchmark-dev curl
          libpq-dev postgresql python3-prometheus-client
          chromium clang libclang-rt-14-dev llvm)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Node.js: only when there is none (a machine may have its own build with npm bundled, which
# Debian's separate npm package would conflict with).
if ! command -v npm >/dev/null 2>&1; then
  missing+=(nodejs npm)
fi
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
# npm ci reinstalls from the lockfile; skipped while node_modules is newer than the lockfile.
if [ ! -f tools/node_modules/.package-lock.json ] ||
   [ tools/package-lock.json -nt tools/node_modules/.package-lock.json ]; then
  echo "installing npm packages into tools/node_modules"
  npm ci --prefix tools --no-audit --no-fund --loglevel=error
fi
