#!/usr/bin/env bash
# The proximity file's range_m reaches ARGoS (as the camera's and the light's do): a proximity file
# with the curve v = a d^2 + b d + c = d^2 - 10 d + 1 (responding to 0.1 m, past the plug-in's 0.05 m
# ray) and range_m 0.08 m, noise off, through `epuck2-fit simulate proximity --like` and the
# calibrated ARGoS proximity sensor (argos-record.sh --like: the row's sensor facing a wall at
# distance_m). Expected, worked by hand (4095 v, 0 beyond range_m, ARGoS rounds to a count):
#   0.02 m: 4095 (0.0004 - 0.2 + 1)  = 3277.638
#   0.06 m: 4095 (0.0036 - 0.6 + 1)  = 1652.742  (beyond the plug-in's 0.05 m ray: the file's reach)
#   0.09 m: 0                          (inside the curve, beyond the file's range_m)
# and a long tail beyond the curve (docs/argos.md: the rays are lengthened to where the tail falls
# below half a count, length x ln(2 x amplitude)): the same curve with long_tail amplitude 100
# counts, length 0.05 m, whose rays reach 0.05 ln 200 = 0.2649 m (ln 100 would stop them at 0.2303 m):
#   0.02 m: 3277.638 + 100 e^-0.4 = 3344.670
#   0.20 m: 100 e^-4 = 1.832           (ARGoS: 2)
#   0.25 m: 100 e^-5 = 0.674           (ARGoS: 1, still inside the rays' reach)
#   0.30 m: 100 e^-6 = 0.248           (ARGoS: 0, beyond the reach, and 0.248 rounds to 0 anyway)
#   usage: proximity_range.sh EPUCK2_FIT ARGOS_LIBDIR WORK_DIR
# Exit 77 (CTest: skipped) when argos3 is not installed.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
FIT="$1"; LIBDIR="$2"; WORK="$3/proximity_range"
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
export EPUCK2_BUILD_DIR="$(dirname "$(dirname "$LIBDIR")")"
rm -rf "$WORK"; mkdir -p "$WORK"
run() { echo "+ $*"; "$@"; }
cat > "$WORK/proximity.json" <<'JSON'
{"kind": "proximity", "parameters": {"a": 1.0, "b": -10.0, "c": 1.0, "range_m": 0.08}}
JSON
cat > "$WORK/tail.json" <<'JSON'
{"kind": "proximity", "parameters": {"a": 1.0, "b": -10.0, "c": 1.0, "range_m": 0.08},
 "effects": {"long_tail": {"amplitude": 100.0, "length_m": 0.05}}}
JSON
# case NAME FILE DISTANCES...: the log (each distance for sensors 0, 3, 6) through simulate and ARGoS.
case_log() {
  local name="$1" file="$2"; shift 2
  {
    echo "# robot: proximity-range"
    echo "distance_m,sensor,value"
    for d in "$@"; do for k in 0 3 6; do echo "$d,$k,0"; done; done
  } > "$WORK/$name.csv"
  run "$FIT" simulate proximity --like "$WORK/$name.csv" --coefficients "$WORK/$file" -o "$WORK/$name.simulated.csv"
  EPUCK2_ARGOS_NOISE=false run "$ROOT/scripts/argos-record.sh" proximity "$WORK/$file" "$WORK/$name.argos.csv" --like "$WORK/$name.csv"
}
case_log range proximity.json 0.02 0.06 0.09
case_log tail tail.json 0.02 0.20 0.25 0.30
python3 - "$WORK" <<'PY'
import csv, math, os, sys
work = sys.argv[1]
curve_002 = 4095 * (0.0004 - 0.2 + 1)
HAND = {"range": {0.02: curve_002, 0.06: 4095 * (0.0036 - 0.6 + 1), 0.09: 0.0},
        "tail": {0.02: curve_002 + 100 * math.exp(-0.4), 0.2: 100 * math.exp(-4), 0.25: 100 * math.exp(-5),
                 0.3: 100 * math.exp(-6)}}
bad = 0
for case, hand in HAND.items():
    for name, tol in (("simulated", 1e-6), ("argos", 0.5 + 1e-6)):
        with open(os.path.join(work, f"{case}.{name}.csv")) as f:
            rows = list(csv.DictReader(l for l in f if not l.startswith("#")))
        if len(rows) != 3 * len(hand):
            print(f"FAIL {case} {name}: {len(rows)} rows, expected {3 * len(hand)}"); bad += 1
        for r in rows:
            d, k, v = float(r["distance_m"]), int(r["sensor"]), float(r["value"])
            want = hand[round(d, 2)]
            ok = abs(v - want) <= tol
            bad += not ok
            print(("ok   " if ok else "FAIL ") + f"{case} {name}: sensor {k} at {d} m: {v:.3f}, by hand {want:.3f}")
sys.exit(1 if bad else 0)
PY
