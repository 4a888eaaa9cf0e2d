#!/usr/bin/env bash
# The closed loop through ARGoS for the proximity and light sensors with a diagnosis's effects
# (issue #20 item 1): a log generated with one effect hidden (the diagnosis tests' generators,
# seeded; the temperature_c column left out, ARGoS has none), diagnosed (`diagnose -o`), then the
# paper's protocol recorded in ARGoS with that file (scripts/argos-record.sh KIND FILE OUT, noise
# off) and with the plug-in's own implementation (`default`). closed_loop_sensors.py compares each
# recorded condition with the generator's truth (its formula and drawn parameters, written in the
# test, not lib/models').
#   usage: closed_loop_sensors.sh KIND CAUSE HIDDEN_LOG EPUCK2_FIT ARGOS_LIBDIR WORK_DIR [SEED]
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
KIND="$1"; CAUSE="$2"; GEN="$3"; FIT="$4"; LIBDIR="$5"; WORK="$6/closed_loop_protocol_${1}_${2}"; SEED="${7:-20}"
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
export EPUCK2_BUILD_DIR="$(dirname "$(dirname "$LIBDIR")")"
rm -rf "$WORK"; mkdir -p "$WORK"
run() { echo "+ $*"; "$@"; }
run "$GEN" "$KIND" "$CAUSE" "$SEED" "$WORK/generated.csv" "$WORK/truth.json"
python3 - "$WORK" <<'PY'
import sys
work = sys.argv[1]
lines = open(f"{work}/generated.csv").read().splitlines()
head = lines[0].split(",")
keep = [i for i, c in enumerate(head) if c != "temperature_c"]
open(f"{work}/log.csv", "w").write("\n".join(",".join(l.split(",")[i] for i in keep) for l in lines) + "\n")
PY
run "$FIT" diagnose "$WORK/log.csv" --kind "$KIND" -o "$WORK/diagnosis.json" > "$WORK/diagnosis.txt"
grep -iE "verdict|finding" "$WORK/diagnosis.txt" | head -5 || true
if [ "$CAUSE" = incidence_angle ]; then
  # The protocol with the wall turned by 30 degrees about its centre: every ray meets it at 30
  # degrees from its normal (and 0.01 (1 - 1 / cos 30) m short of the nominal distance, the face
  # turning about the wall's centre line); distances from 25 mm, where the turned wall clears the body.
  record() {  # coefficients|default out_dir
    mkdir -p "$2"
    sed -e "s|output_dir=\"[^\"]*\"|output_dir=\"$2\"|" -e 's|distances="[^"]*"|distances="0.025:0.005:0.05"|' \
        -e 's|<body position="0.5,0,0" orientation="0,0,0" />|<body position="0.5,0,0" orientation="30,0,0" />|' \
        "$ROOT/argos/experiments/proximity.argos" > "$2/exp.argos"
    if [ "$1" = default ]; then
      sed -i -e 's|implementation="calibrated"|implementation="default"|' -e 's| coefficients="[^"]*"||' "$2/exp.argos"
    else
      sed -i -e "s|coefficients=\"[^\"]*\"|coefficients=\"$1\"|" "$2/exp.argos"
    fi
    grep -q 'orientation="30,0,0"' "$2/exp.argos" || { echo "FAIL: the wall was not turned"; exit 1; }
    ARGOS_PLUGIN_PATH="$LIBDIR" argos3 -n -z -c "$2/exp.argos" > "$2/log" 2>&1 || { tail -20 "$2/log"; exit 1; }
  }
  run record "$WORK/diagnosis.json" "$WORK/argos_diagnosis"
  run record default "$WORK/argos_plugin"
else
  run "$ROOT/scripts/argos-record.sh" "$KIND" "$WORK/diagnosis.json" "$WORK/argos_diagnosis"
  run "$ROOT/scripts/argos-record.sh" "$KIND" default "$WORK/argos_plugin"
fi
python3 "$HERE/closed_loop_sensors.py" "$WORK"
