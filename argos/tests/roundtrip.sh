#!/usr/bin/env bash
# The ARGoS round trip for one kind: fit the shipped logs (data/raw/KIND) with epuck2-fit, record
# the protocol in ARGoS with the calibrated plug-in and that coefficient file, refit the recorded
# logs, and check that every coefficient comes back (compare_coefficients.py). default_KIND
# records with the E-Puck2 plug-in's own implementations and checks for its published
# coefficients.
#   usage: roundtrip.sh KIND EPUCK2_FIT ARGOS_LIBDIR WORK_DIR
# Exit 77 (CTest: skipped) when argos3 is not installed.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
KIND="$1"; FIT="$2"; LIBDIR="$3"; WORK="$4/$1"
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
export EPUCK2_BUILD_DIR="$(dirname "$(dirname "$LIBDIR")")"
rm -rf "$WORK"; mkdir -p "$WORK/recorded"
run() { echo "+ $*"; "$@"; }
case "$KIND" in
  default_*)
    kind="${KIND#default_}"
    fitkind="$kind"
    run "$ROOT/scripts/argos-record.sh" "$kind" default "$WORK/recorded"
    run "$FIT" "$fitkind" "$WORK"/recorded/*.csv -o "$WORK/refit.json" > "$WORK/refit.txt"
    run python3 "$HERE/compare_coefficients.py" "$kind" "$WORK/refit.json" plugin
    ;;
  *)
    run "$FIT" "$KIND" "$ROOT"/data/raw/"$KIND"/*.csv -o "$WORK/fitted.json" > "$WORK/fitted.txt"
    run "$ROOT/scripts/argos-record.sh" "$KIND" "$WORK/fitted.json" "$WORK/recorded"
    run "$FIT" "$KIND" "$WORK"/recorded/*.csv -o "$WORK/refit.json" > "$WORK/refit.txt"
    run python3 "$HERE/compare_coefficients.py" "$KIND" "$WORK/refit.json" "$WORK/fitted.json"
    ;;
esac
