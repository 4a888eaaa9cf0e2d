#!/usr/bin/env bash
# Installs everything the project needs on Debian 12 (bookworm): compiler, CMake and Ninja, Ceres, Eigen,
# CLI11, nlohmann-json, gnuplot-iostream with gnuplot-nox, GoogleTest, Google Benchmark; and for the
# side-by-side benchmark (bench/side_by_side.py) python3-scipy and python3-lmfit.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
PACKAGES=(
  build-essential cmake ninja-build
  libceres-dev libeigen3-dev libcli11-dev nlohmann-json3-dev
  libgnuplot-iostream-dev gnuplot-nox libboost-iostreams-dev libboost-filesystem-dev libboost-system-dev
  libgtest-dev libbenchmark-dev
  python3 python3-numpy python3-scipy python3-lmfit
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}" >&2
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "install-deps: all packages present" >&2
fi
