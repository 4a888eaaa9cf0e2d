#!/usr/bin/env bash
# The README's first command: installs what is needed, builds, and runs the main job on the
# shipped data: every fit (battery and sensors), the coefficient header, the reports (Table 5
# among them) and the plots, into data/fitted.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
scripts/regenerate.sh "$@"
