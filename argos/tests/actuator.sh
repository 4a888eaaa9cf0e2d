#!/usr/bin/env bash
# The calibrated differential steering actuator in ARGoS (issue #20's wheel tests), on the drive
# protocol (argos/experiments/drive.argos) with drive files made here from data/fitted/drive.json:
#   cap       a 20 cm/s command runs at the firmware's 1100 steps/s (the plug-in's default: 20 cm/s);
#   accel     a 10 cm/s step with accel_limit 50 cm/s^2 ramps as a t^2 / 2 (the encoders, row by row);
#   slip      slip_time_constant_s 0.3: the ToF's body travel lags the encoders' wheel travel by u tau;
#   still     encoder noise 3 steps: a robot standing still reads its count exactly, every row;
#   warning   the ToF with a slip file on the default steering warns that the body ignores it.
# Expected values are the effects' closed forms (actuator_check.py), not the plug-in's code.
#   usage: actuator.sh ARGOS_LIBDIR WORK_DIR
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
LIBDIR="$1"; WORK="$2/actuator"
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
rm -rf "$WORK"; mkdir -p "$WORK"
export ARGOS_PLUGIN_PATH="$LIBDIR"
python3 - "$ROOT/data/fitted/drive.json" "$WORK" <<'PY'
import json, sys
base = json.load(open(sys.argv[1]))
def write(name, parameters=None, effects=None, noise=None):
    d = json.loads(json.dumps(base))
    d["parameters"].update(parameters or {})
    if effects: d["effects"] = effects
    if noise: d["noise"]["encoder"].update(noise)
    json.dump(d, open(f"{sys.argv[2]}/{name}.json", "w"))
write("cap", {"slip_time_constant_s": 0.0})
write("accel", {"slip_time_constant_s": 0.0}, {"accel_limit": {"accel_cm_s2": 50.0}})
write("slip", {"slip_time_constant_s": 0.3})
write("still", {"slip_time_constant_s": 0.0}, None, {"sd": 3.0})
write("covariate", {}, {"covariate:temperature_c": {"slope": 0.5, "centre": 25.0}})
PY
run() {  # name speeds noise actuator_implementation
  local dir="$WORK/$1"; mkdir -p "$dir"
  sed -e "s|output_dir=\"[^\"]*\"|output_dir=\"$dir\"|" -e "s|coefficients=\"[^\"]*\"|coefficients=\"$WORK/${5:-$1}.json\"|g" \
      -e "s|speeds=\"[^\"]*\"|speeds=\"$2\"|" -e "s|noise=\"false\"|noise=\"$3\"|g" \
      -e "s|<differential_steering implementation=\"calibrated\"|<differential_steering implementation=\"$4\"|" \
      "$ROOT/argos/experiments/drive.argos" > "$dir/exp.argos"
  argos3 -n -z -c "$dir/exp.argos" > "$dir/log" 2>&1 || { cat "$dir/log"; echo "FAIL: argos3 ($1)"; exit 1; }
}
run cap 20 false calibrated
run default 20 false default cap
run accel 10 false calibrated
run slip 10 false calibrated
run still 10 true calibrated
# A drive file with slip (or any drive effect) read by the ToF of a robot whose steering is not the
# calibrated one: a warning at Init that the body does not move by the file, naming the effects the
# ToF applies itself; the file with no drive effect (cap, above) gives no such warning.
run slip_default 10 false default slip
grep -q "calibrated epuck2_tof: $WORK/slip.json: the robot's differential_steering is not implementation=\"calibrated\": the file's speed limit, slip and other drive effects do not move the body, only the ToF's own (.*tof_scale.*) apply" "$WORK/slip_default/log" ||
  { cat "$WORK/slip_default/log"; echo "FAIL: no warning that the default steering ignores the file's slip"; exit 1; }
! grep -q "calibrated epuck2_tof: .*is not implementation=\"calibrated\"" "$WORK/default/log" || { cat "$WORK/default/log"; echo "FAIL: a warning about drive effects for a file with none"; exit 1; }
echo "ok   default steering with a slip file: $(grep -o "the robot's differential_steering is not[^:]*" "$WORK/slip_default/log" | head -1)"
# A refusal: an effect ARGoS cannot apply stops it at Init, naming the effect and why.
mkdir -p "$WORK/covariate"
sed -e "s|output_dir=\"[^\"]*\"|output_dir=\"$WORK/covariate\"|" -e "s|coefficients=\"[^\"]*\"|coefficients=\"$WORK/covariate.json\"|g" \
    "$ROOT/argos/experiments/drive.argos" > "$WORK/covariate/exp.argos"
if argos3 -n -z -c "$WORK/covariate/exp.argos" > "$WORK/covariate/log" 2>&1; then echo "FAIL: ARGoS ran with a covariate effect"; exit 1; fi
grep -q "calibrated differential_steering: .*covariate.json:[0-9]*:[0-9]*: effects.covariate:temperature_c: the calibrated differential_steering actuator cannot apply it in ARGoS: it needs the log column 'temperature_c', which ARGoS does not have" "$WORK/covariate/log" ||
  { cat "$WORK/covariate/log"; echo "FAIL: no message naming the covariate"; exit 1; }
echo "ok   refusal: $(grep -o "effects.covariate:temperature_c: [^(]*" "$WORK/covariate/log" | head -1)"
python3 "$HERE/actuator_check.py" "$WORK"
