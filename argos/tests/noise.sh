#!/usr/bin/env bash
# The reading noise in ARGoS: fit the shipped logs (data/raw/KIND) with epuck2-fit, record the
# protocol in ARGoS with that coefficient file twice with the same seed, noise="false" and
# noise="true", and check that the noisy readings differ from the noiseless ones by the file's
# measured reading noise (noise_sd.py: within 10 % of noise.<channel>.sd, per sensor).
#   usage: noise.sh KIND EPUCK2_FIT ARGOS_LIBDIR WORK_DIR     (KIND: proximity, ground, light, drive)
# Exit 77 (CTest: skipped) when argos3 is not installed.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
KIND="$1"; FIT="$2"; LIBDIR="$3"; WORK="$4/noise_$1"
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
export EPUCK2_BUILD_DIR="$(dirname "$(dirname "$LIBDIR")")"
rm -rf "$WORK"; mkdir -p "$WORK"
run() { echo "+ $*"; "$@"; }
# Enough readings for a standard deviation to within a few per cent (the protocols' defaults
# record 20-40 per condition).
case "$KIND" in proximity) export EPUCK2_ARGOS_SAMPLES=200;; ground) export EPUCK2_ARGOS_SAMPLES=120;; light) export EPUCK2_ARGOS_SAMPLES=60;; esac
run "$FIT" "$KIND" "$ROOT"/data/raw/"$KIND"/*.csv -o "$WORK/fitted.json" > "$WORK/fitted.txt"
EPUCK2_ARGOS_NOISE=false run "$ROOT/scripts/argos-record.sh" "$KIND" "$WORK/fitted.json" "$WORK/quiet"
EPUCK2_ARGOS_NOISE=true run "$ROOT/scripts/argos-record.sh" "$KIND" "$WORK/fitted.json" "$WORK/noisy"
run python3 "$HERE/noise_sd.py" "$KIND" "$WORK/quiet" "$WORK/noisy" "$WORK/fitted.json"
