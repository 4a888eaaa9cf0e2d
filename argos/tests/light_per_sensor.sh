#!/usr/bin/env bash
# One light model everywhere (issue #22): a light coefficient file whose per-sensor gammas differ
# (0.05, 0.06, ..., 0.12 m) and whose per-sensor noise sds differ a lot (1 to 60 counts), run
#   1. noiseless, one light of intensity 1 at 0.2 m on each sensor's axis, through
#      `epuck2-fit simulate light --like` and the calibrated ARGoS light sensor (argos-record.sh
#      --like): each against Eq. 2 worked by hand from the file's gammas, and against each other,
#      to the reading's resolution (ARGoS rounds to a count, simulate writes the expected value);
#   1b. noiseless, the same file with range_m 0.25 m and the light at 0.2 and 0.3 m: beyond the
#      file's range no light is seen (4095), inside it Eq. 2 holds (both tools);
#   2. with noise, 400 readings per sensor at a fixed pose (0.3 m, intensity 1), the uniform noise
#      (noise_distribution="uniform", the plug-in's) and the Gaussian: each sensor's spread against
#      its own sd (light_per_sensor.py, computed apart from the code under test).
#   usage: light_per_sensor.sh EPUCK2_FIT ARGOS_LIBDIR WORK_DIR
# Exit 77 (CTest: skipped) when argos3 is not installed.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
FIT="$1"; LIBDIR="$2"; WORK="$3/light_per_sensor"
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
export EPUCK2_BUILD_DIR="$(dirname "$(dirname "$LIBDIR")")"
rm -rf "$WORK"; mkdir -p "$WORK"
run() { echo "+ $*"; "$@"; }
run python3 "$HERE/light_per_sensor.py" write "$WORK"
run "$FIT" simulate light --like "$WORK/gammas.csv" --coefficients "$WORK/light.json" -o "$WORK/gammas.simulated.csv"
EPUCK2_ARGOS_NOISE=false run "$ROOT/scripts/argos-record.sh" light "$WORK/light.json" "$WORK/gammas.argos.csv" --like "$WORK/gammas.csv"
run "$FIT" simulate light --like "$WORK/range.csv" --coefficients "$WORK/range.json" -o "$WORK/range.simulated.csv"
EPUCK2_ARGOS_NOISE=false run "$ROOT/scripts/argos-record.sh" light "$WORK/range.json" "$WORK/range.argos.csv" --like "$WORK/range.csv"
for dist in uniform gaussian; do
  EPUCK2_ARGOS_NOISE=true EPUCK2_ARGOS_NOISE_DISTRIBUTION=$dist \
    run "$ROOT/scripts/argos-record.sh" light "$WORK/light.json" "$WORK/noise.$dist.csv" --like "$WORK/noise.csv"
done
run python3 "$HERE/light_per_sensor.py" check "$WORK"
