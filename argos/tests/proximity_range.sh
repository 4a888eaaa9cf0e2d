#!/usr/bin/env bash
# The proximity file's range_m reaches ARGoS (as the camera's and the light's do): a proximity file
# with the curve v = a d^2 + b d + c = d^2 - 10 d + 1 (responding to 0.1 m, past the plug-in's 0.05 m
# ray) and range_m 0.08 m, noise off, through `epuck2-fit simulate proximity --like` and the
# calibrated ARGoS proximity sensor (argos-record.sh --like: the row's sensor facing a wall at
# distance_m). Expected, worked by hand (4095 v, 0 beyond range_m, ARGoS rounds to a count):
#   0.02 m: 4095 (0.0004 - 0.2 + 1)  = 3277.638
#   0.06 m: 4095 (0.0036 - 0.6 + 1)  = 1652.742  (beyond the plug-in's 0.05 m ray: the file's reach)
#   0.09 m: 0                          (inside the curve, beyond the file's range_m)
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
{
  echo "# robot: proximity-range"
  echo "distance_m,sensor,value"
  for d in 0.02 0.06 0.09; do for k in 0 3 6; do echo "$d,$k,0"; done; done
} > "$WORK/range.csv"
run "$FIT" simulate proximity --like "$WORK/range.csv" --coefficients "$WORK/proximity.json" -o "$WORK/range.simulated.csv"
EPUCK2_ARGOS_NOISE=false run "$ROOT/scripts/argos-record.sh" proximity "$WORK/proximity.json" "$WORK/range.argos.csv" --like "$WORK/range.csv"
python3 - "$WORK" <<'PY'
import csv, os, sys
work = sys.argv[1]
HAND = {0.02: 4095 * (0.0004 - 0.2 + 1), 0.06: 4095 * (0.0036 - 0.6 + 1), 0.09: 0.0}
bad = 0
for name, tol in (("simulated", 1e-6), ("argos", 0.5 + 1e-6)):
    with open(os.path.join(work, f"range.{name}.csv")) as f:
        rows = list(csv.DictReader(l for l in f if not l.startswith("#")))
    if len(rows) != 9:
        print(f"FAIL {name}: {len(rows)} rows, expected 9"); bad += 1
    for r in rows:
        d, k, v = float(r["distance_m"]), int(r["sensor"]), float(r["value"])
        want = HAND[round(d, 2)]
        ok = abs(v - want) <= tol
        bad += not ok
        print(("ok   " if ok else "FAIL ") + f"{name}: sensor {k} at {d} m: {v:.3f}, by hand {want:.3f}")
sys.exit(1 if bad else 0)
PY
