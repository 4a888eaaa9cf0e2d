#!/usr/bin/env bash
# Configures and builds everything (Release) into build/; the CLI lands at build/bin/epuck2-fit.
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS="${EPUCK2_JOBS:-$(nproc 2>/dev/null || echo 2)}"
LAUNCHER=()
# ccache, when installed, makes rebuilds in several checkouts cheap; the build does not need it.
if command -v ccache >/dev/null 2>&1; then LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DEPUCK2_BUILD_APPS=ON "${LAUNCHER[@]}" >/dev/null
cmake --build build -j"$JOBS"
