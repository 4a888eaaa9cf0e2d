#!/usr/bin/env bash
# Configures (Release) and builds into build/ what a user runs: the libraries and the CLI
# (build/bin/epuck2-fit, all that scripts/regenerate.sh needs). The tests and benchmarks are left
# for the test command.
#   scripts/build.sh          the CMake target `product`
#   scripts/build.sh --argos  that and, when ARGoS is installed, the ARGoS plug-in (build/lib/argos3)
#   scripts/build.sh --all    everything: the plug-in, the tests, the benchmarks and the examples too
set -euo pipefail
cd "$(dirname "$0")/.."
TARGET=(--target product)
for arg in "$@"; do
  case "$arg" in
    --all) TARGET=() ;;
    --argos) TARGET=(--target product argos_plugin) ;;
    -h|--help) sed -n '2,7p' "$0"; exit 0 ;;
    *) echo "build: unknown option '$arg' (expected --argos or --all)" >&2; exit 2 ;;
  esac
done
JOBS="${EPUCK2_JOBS:-$(nproc 2>/dev/null || echo 2)}"
LAUNCHER=()
# ccache, when installed, makes rebuilds in several checkouts cheap; the build does not need it.
if command -v ccache >/dev/null 2>&1; then LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
# Ninja, when installed (scripts/install-deps.sh installs it): it starts a unit as soon as the
# headers it needs exist, where make waits for every library a target links to be built first; on
# two cores that keeps both busy through the chain fit -> calibrate -> diagnose -> plot -> CLI
# (bench/README.md, "The README's two commands"). A build/ configured before keeps its generator.
GENERATOR=()
if [ ! -f build/CMakeCache.txt ] && command -v ninja >/dev/null 2>&1; then GENERATOR=(-G Ninja); fi
cmake -S . -B build "${GENERATOR[@]}" -DCMAKE_BUILD_TYPE=Release -DEPUCK2_BUILD_APPS=ON "${LAUNCHER[@]}" >/dev/null
cmake --build build -j"$JOBS" "${TARGET[@]}"
