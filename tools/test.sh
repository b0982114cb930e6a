#!/usr/bin/env bash
# Builds Lambert and runs every test (ctest). Installs missing packages first.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/build.sh
cd build
ctest --output-on-failure -j2 --timeout 300
