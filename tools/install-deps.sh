#!/usr/bin/env bash
# Installs the Debian 12 packages Lambert builds with, if any is missing (apt-get; sudo when not root).
set -euo pipefail
packages=(build-essential cmake ninja-build pkg-config
          libcgal-dev libopenmesh-dev libembree-dev libcpp-httplib-dev nlohmann-json3-dev
          libgtest-dev libbenchmark-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "installing: ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
