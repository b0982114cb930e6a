#!/usr/bin/env bash
# The main job on a fresh machine: install what is missing, build, and solve the bundled Cornell box.
# Writes out/cornell-box.result.json and prints a summary (patches, time, energy balance, mean
# illuminance per surface).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/build.sh
mkdir -p out
build/lambert solve scenes/cornell-box.json -o out/cornell-box.result.json
