#!/usr/bin/env bash
# ARGoS's Reset with the calibrated models (the wheels, the encoders, the ToF, the battery): an
# experiment run, reset with CSimulator::Reset() and run again in one process (argos_reset_check)
# must give the same readings and poses, tick by tick, to the last digit. The first run starts from
# Init, so it is the expected value of the second. The drive file has every state a run builds up:
# accel_limit (the wheels' speeds), slip (the body's lag), latency (the ToF's delay line), encoder
# and ToF noise (reseeded by Reset); the battery is the calibrated cubic, as the plug-in computes it
# (behaviour="argos") and corrected (its root hints kept between ticks). Two robots on the
# calibrated wheels, so that a state shared between robots shows too, and a third on the plug-in's
# wheels (its calibrated encoders then count the wheels' speeds themselves). No command at the first
# tick: the wheels run on what the actuator holds, nothing after Init and nothing after Reset.
# And the same experiment with threads="2" reads as with threads="0". The runs must also move: a reset that is never tested
# against a moved state proves nothing.
#   usage: reset.sh ARGOS_LIBDIR WORK_DIR RESET_CHECK_BINARY
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
LIBDIR="$1"; WORK="$2/reset"; CHECK="$3"
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
rm -rf "$WORK"; mkdir -p "$WORK"
export ARGOS_PLUGIN_PATH="$LIBDIR"
python3 - "$ROOT/data/fitted/drive.json" "$WORK/drive.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d["parameters"]["slip_time_constant_s"] = 0.3
d.setdefault("effects", {})
d["effects"]["accel_limit"] = {"accel_cm_s2": 40.0}
d["effects"]["latency"] = {"delay_s": 0.25}
d["noise"]["encoder"]["sd"] = 2.0
json.dump(d, open(sys.argv[2], "w"))
PY
robot() {  # id x y controller behaviour
  cat <<XML
    <e-puck2 id="$1">
      <body position="$2,$3,0" orientation="0,0,0" />
      <controller config="$4" />
      <epuck2_battery discharge_model="calibrated" coefficients="$ROOT/data/fitted/battery.json" model="cubic" behaviour="$5" start_charge="1.0" />
    </e-puck2>
XML
}
cat > "$WORK/exp.argos" <<XML
<?xml version="1.0" ?>
<argos-configuration>
  <framework>
    <system threads="0" />
    <experiment length="0" ticks_per_second="10" random_seed="321" />
  </framework>
  <controllers>
    <epuck2_recorder_controller id="recorder" library="libepuck2_argos_protocols">
      <actuators>
        <differential_steering implementation="calibrated" coefficients="$WORK/drive.json" />
      </actuators>
      <sensors>
        <epuck2_tof implementation="calibrated" coefficients="$WORK/drive.json" noise="true" />
        <epuck2_encoder implementation="calibrated" coefficients="$WORK/drive.json" noise="true" />
        <epuck2_battery implementation="default" />
      </sensors>
      <params />
    </epuck2_recorder_controller>
    <epuck2_recorder_controller id="default_wheels" library="libepuck2_argos_protocols">
      <actuators>
        <differential_steering implementation="default" />
      </actuators>
      <sensors>
        <epuck2_tof implementation="calibrated" coefficients="$WORK/drive.json" noise="true" />
        <epuck2_encoder implementation="calibrated" coefficients="$WORK/drive.json" noise="true" />
        <epuck2_battery implementation="default" />
      </sensors>
      <params />
    </epuck2_recorder_controller>
  </controllers>
  <arena size="4, 4, 1" center="0,0,0.5">
    <box id="obstacle" size="0.02,3,0.2" movable="false">
      <body position="1.2,0,0" orientation="0,0,0" />
    </box>
$(robot ep0 0 -0.5 recorder argos)
$(robot ep1 0 0.5 recorder corrected)
$(robot ep2 0 1.2 default_wheels argos)
  </arena>
  <physics_engines>
    <dynamics2d id="dyn2d" />
  </physics_engines>
  <media>
    <led id="leds" />
  </media>
  <visualization />
</argos-configuration>
XML
"$CHECK" "$WORK/exp.argos" 90 "$WORK/first.csv" "$WORK/second.csv" > "$WORK/log" 2>&1 ||
  { cat "$WORK/log"; echo "FAIL: argos_reset_check"; exit 1; }
# The same experiment with ARGoS's threads (threads="2": the robots' sensors and actuators updated in
# parallel) must read what the single-threaded run read: the calibrated parts share the file cache
# and the drive registry between robots.
sed 's/<system threads="0" \/>/<system threads="2" \/>/' "$WORK/exp.argos" > "$WORK/threads.argos"
grep -q 'threads="2"' "$WORK/threads.argos" || { echo "FAIL: no threads attribute to set"; exit 1; }
"$CHECK" "$WORK/threads.argos" 90 "$WORK/threads_first.csv" "$WORK/threads_second.csv" > "$WORK/threads.log" 2>&1 ||
  { cat "$WORK/threads.log"; echo "FAIL: argos_reset_check with threads"; exit 1; }
cmp "$WORK/first.csv" "$WORK/threads_first.csv" && cmp "$WORK/second.csv" "$WORK/threads_second.csv" ||
  { echo "FAIL: with threads=\"2\" the readings differ from the single-threaded run's"; exit 1; }
echo "ok   threads=\"2\": the same readings as threads=\"0\", both runs"
python3 - "$WORK/first.csv" "$WORK/second.csv" <<'PY'
import csv, sys
first = list(csv.DictReader(open(sys.argv[1])))
second = list(csv.DictReader(open(sys.argv[2])))
if len(first) != 270 or len(second) != 270:
    sys.exit(f"FAIL: expected 90 ticks x 3 robots in each run, got {len(first)} and {len(second)} rows")
# The first run moves every state away from its start (else the test shows nothing).
for r in ("ep0", "ep1", "ep2"):
    rows = [x for x in first if x["robot"] == r]
    t30 = rows[29]
    if not (int(t30["left_steps"]) > 100 and int(t30["right_steps"]) > 100):
        sys.exit(f"FAIL: {r} did not drive forward in the first 3 s: {t30}")
    if int(rows[49]["right_steps"]) - int(rows[49]["left_steps"]) < 50:
        sys.exit(f"FAIL: {r} did not turn: {rows[49]}")
    if not int(rows[-1]["left_steps"]) < int(rows[59]["left_steps"]):
        sys.exit(f"FAIL: {r} did not reverse: {rows[59]} then {rows[-1]}")
    tofs = {x["tof_mm"] for x in rows}
    if len(tofs) < 20:
        sys.exit(f"FAIL: {r}'s ToF read only {len(tofs)} values")
    if not float(rows[-1]["charge"]) < 1.0:
        sys.exit(f"FAIL: {r}'s battery did not discharge: {rows[-1]['charge']}")
# The second run is the first, row by row and to the last digit.
for a, b in zip(first, second):
    if a != b:
        sys.exit(f"FAIL: after Reset, tick {b['tick']} of {b['robot']} differs from the first run:\n  first  {a}\n  second {b}")
print(f"ok   Reset: 90 ticks x 3 robots read the same after Reset (wheels, encoders, ToF, battery, pose); "
      f"ep0 at the end: steps {first[-3]['left_steps']}/{first[-3]['right_steps']}, ToF {first[-3]['tof_mm']} mm, charge {first[-3]['charge']}")
PY
