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
KIND="$1"; CAUSE="$2"; GEN="$3"; FIT="$4"; LIBDIR="$5"; WORK="$6/closed_loop_${1}_${2}"; SEED="${7:-20}"
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
run "$ROOT/scripts/argos-record.sh" "$KIND" "$WORK/diagnosis.json" "$WORK/argos_diagnosis"
run "$ROOT/scripts/argos-record.sh" "$KIND" default "$WORK/argos_plugin"
python3 "$HERE/closed_loop_sensors.py" "$WORK"
