#!/usr/bin/env bash
# Hostile coefficient files against every calibrated part of the plug-in (argos/tests/hostile.py).
#   usage: hostile.sh ARGOS_LIBDIR WORK_DIR
set -euo pipefail
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
exec python3 "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/hostile.py" "$1" "$2"
