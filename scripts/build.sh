#!/usr/bin/env bash
# Configures and builds everything (Release) into build/; the CLI lands at build/bin/epuck2-fit.
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS="${EPUCK2_JOBS:-$(nproc 2>/dev/null || echo 2)}"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$JOBS"
