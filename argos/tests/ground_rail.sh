#!/usr/bin/env bash
# The calibrated ARGoS ground sensor keeps its 10-bit rails: a ground file whose white reads above
# 1023 (offset 100 + gain 1000 = 1100 counts) through the ground protocol (the whole floor at each
# grey, argos-record.sh), noise off and on (the shipped file's noise section, sd about 5 counts).
# Expected, worked by hand (docs/sensor-models.md: value = offset + gain x grey, rounded and
# clamped to the ground's 0..1023):
#   noise off: every row reads clamp(round(100 + 1000 grey), 0, 1023): 100 at grey 0, 1023 from
#              grey 0.923 (923 + 100) up, 1023 at white;
#   noise on:  every reading within 0..1023, and white (mean 1100, 15 sd above the rail) 1023.
# And a file inside the rails (offset 60, gain 900: white 960) reads round(60 + 900 grey) exactly.
#   usage: ground_rail.sh ARGOS_LIBDIR WORK_DIR
# Exit 77 (CTest: skipped) when argos3 is not installed.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
LIBDIR="$1"; WORK="$2/ground_rail"
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
export EPUCK2_BUILD_DIR="$(dirname "$(dirname "$LIBDIR")")"
rm -rf "$WORK"; mkdir -p "$WORK"
run() { echo "+ $*"; "$@"; }
python3 - "$ROOT/data/fitted/ground.json" "$WORK" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
for name, gain, offset in (("bright", 1000.0, 100.0), ("inside", 900.0, 60.0)):
    j["parameters"]["gain"] = [gain] * 3
    j["parameters"]["offset"] = [offset] * 3
    json.dump(j, open(f"{sys.argv[2]}/{name}.json", "w"), indent=1)
PY
EPUCK2_ARGOS_NOISE=false run "$ROOT/scripts/argos-record.sh" ground "$WORK/bright.json" "$WORK/bright_quiet"
EPUCK2_ARGOS_NOISE=true run "$ROOT/scripts/argos-record.sh" ground "$WORK/bright.json" "$WORK/bright_noisy"
EPUCK2_ARGOS_NOISE=false run "$ROOT/scripts/argos-record.sh" ground "$WORK/inside.json" "$WORK/inside_quiet"
python3 - "$WORK" <<'PY'
import csv, glob, math, sys
work = sys.argv[1]
def rows(d):
    files = sorted(glob.glob(f"{work}/{d}/*.csv"))
    if not files:
        sys.exit(f"no log in {work}/{d}")
    out = []
    for p in files:
        with open(p) as f:
            out += [(float(r["grey"]), int(r["sensor"]), float(r["value"])) for r in csv.DictReader(l for l in f if not l.startswith("#"))]
    return out
bad = 0
def check(ok, what):
    global bad
    if not ok:
        bad += 1
        if bad <= 10:
            print("FAIL", what)
for d, gain, offset in (("bright_quiet", 1000.0, 100.0), ("inside_quiet", 900.0, 60.0)):
    r = rows(d)
    for g, s, v in r:
        want = min(max(offset + gain * g, 0.0), 1023.0)
        check(abs(v - want) <= 0.5 + 1e-3, f"{d}: grey {g} sensor {s} reads {v}, expected {want:.3f} rounded")
    print(f"{d}: {len(r)} readings, from {min(v for _, _, v in r):g} to {max(v for _, _, v in r):g}")
r = rows("bright_noisy")
whites = [v for g, _, v in r if g == 1.0]
check(len(whites) >= 30, f"bright_noisy: {len(whites)} readings over white")
for g, s, v in r:
    check(0 <= v <= 1023, f"bright_noisy: grey {g} sensor {s} reads {v}, outside the ground's 0..1023")
check(all(v == 1023 for v in whites), f"bright_noisy: white reads {sorted(set(whites))}, expected 1023 only")
spread = [v for g, _, v in r if abs(g - 0.5) < 0.01]
check(len(set(spread)) > 3, f"bright_noisy: mid-grey readings {sorted(set(spread))}: the noise is on")
print(f"bright_noisy: {len(r)} readings, {len(whites)} over white, max {max(v for _, _, v in r):g}")
sys.exit(1 if bad else 0)
PY
