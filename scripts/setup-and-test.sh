#!/usr/bin/env bash
# The README's second command: installs what is needed, builds, and runs every test (CTest).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
cd build
ctest --output-on-failure -j"${EPUCK2_JOBS:-$(nproc 2>/dev/null || echo 2)}"
