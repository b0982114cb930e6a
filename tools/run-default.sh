#!/usr/bin/env bash
# The main job on a fresh machine: install what is missing, build, and solve the bundled Cornell box.
# Writes out/cornell-box.result.json and prints a summary (patches, time, energy balance, mean
# illuminance per surface), then draws the result: out/cornell-box.png (smooth shading) and
# out/cornell-box.illuminance.png (false colour of each patch's illuminance, with its scale).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/build.sh
mkdir -p out
build/lambert solve scenes/cornell-box.json -o out/cornell-box.result.json
build/lambert render out/cornell-box.result.json -o out/cornell-box.png --smooth
build/lambert render out/cornell-box.result.json -o out/cornell-box.illuminance.png --false-color illuminance
