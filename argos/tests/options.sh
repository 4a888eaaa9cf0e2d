#!/usr/bin/env bash
# The calibrated sensors' XML options in ARGoS: a robot's own coefficient set (robot="ID"), the
# Gaussian noise of fits.<name>.noise_sd, and a bad coefficient file stopping ARGoS at Init with a
# message naming the file.
#   usage: options.sh ARGOS_LIBDIR WORK_DIR
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
LIBDIR="$1"; WORK="$2/options"
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
rm -rf "$WORK"; mkdir -p "$WORK"
export ARGOS_PLUGIN_PATH="$LIBDIR"
# A proximity file with a robot set and a noise level.
python3 - "$ROOT/data/fitted/proximity.json" "$WORK/p.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d["robots"] = {"r1": {"parameters": {"a": 150.0, "b": -25.0, "c": 0.9}}}
d["fits"] = {"proximity": {"noise_sd": 0.01}}
json.dump(d, open(sys.argv[2], "w"))
PY
experiment() {  # out_dir sensor_attributes distances samples
  sed -e "s|output_dir=\"[^\"]*\"|output_dir=\"$1\"|" \
      -e "s|coefficients=\"[^\"]*\" noise=\"false\"|$2|" \
      -e "s|distances=\"[^\"]*\"|distances=\"$3\"|" -e "s|samples=\"[^\"]*\"|samples=\"$4\"|" \
      "$ROOT/argos/experiments/proximity.argos" > "$1/exp.argos"
}
fail() { echo "FAIL: $*"; exit 1; }

# 1. robot="r1": 150 d^2 - 25 d + 0.9 at 20 mm, noiseless
mkdir -p "$WORK/robot"
experiment "$WORK/robot" "coefficients=\"$WORK/p.json\" robot=\"r1\" noise=\"false\"" "0.02:0.01:0.02" 5
argos3 -n -z -c "$WORK/robot/exp.argos" > "$WORK/robot/log" 2>&1 || { cat "$WORK/robot/log"; fail "argos3"; }
got=$(tail -n 1 "$WORK/robot/proximity_argos-epuck2.csv" | cut -d, -f4)
want=$(python3 -c "print(round((150*0.02**2 - 25*0.02 + 0.9)*4095))")
[ "$got" = "$want" ] || fail "robot r1 reads $got at 20 mm, expected $want"
echo "ok   robot=\"r1\": $got at 20 mm (the robot's set)"

# 2. noise="true" with fits.proximity.noise_sd = 0.01: a Gaussian of 41 counts
mkdir -p "$WORK/noise"
experiment "$WORK/noise" "coefficients=\"$WORK/p.json\" noise=\"true\"" "0.02:0.01:0.02" 400
argos3 -n -z -c "$WORK/noise/exp.argos" > "$WORK/noise/log" 2>&1 || { cat "$WORK/noise/log"; fail "argos3"; }
python3 - "$WORK/noise/proximity_argos-epuck2.csv" <<'PY' || fail "noise"
import statistics, sys
v = [int(l.split(",")[3]) for l in open(sys.argv[1]) if l[0].isdigit()]
sd = statistics.stdev(v)
print(f"ok   noise: {len(v)} readings, sd {sd:.1f} counts (noise_sd 0.01 x 4095 = 41)" if 35 < sd < 47 else f"FAIL sd {sd}")
sys.exit(0 if 35 < sd < 47 else 1)
PY

# 3. a missing coefficient file stops ARGoS at Init, naming the sensor and the file
mkdir -p "$WORK/missing"
experiment "$WORK/missing" "coefficients=\"$WORK/nope.json\"" "0.02:0.01:0.02" 1
if argos3 -n -z -c "$WORK/missing/exp.argos" > "$WORK/missing/log" 2>&1; then fail "argos3 ran with a missing file"; fi
grep -q "calibrated epuck2_proximity: $WORK/nope.json: cannot open the coefficient file" "$WORK/missing/log" ||
  { cat "$WORK/missing/log"; fail "no message naming the file"; }
echo "ok   missing file: $(grep -o 'calibrated epuck2_proximity: .*' "$WORK/missing/log")"
