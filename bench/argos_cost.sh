#!/usr/bin/env bash
# What the calibrated ARGoS plug-in costs against the E-Puck2 plug-in's own implementations:
# N robots driving in circles for a simulated time, each sensor alone and each battery model,
# calibrated against default. Measures the CPU time (user + sys) of the argos3 process, not the
# wall time: on a machine shared with other jobs the wall time mostly measures the others. The
# default and the calibrated run of a row alternate (ABBA: A B, then B A, ...), so that a drift
# of the machine's load hits both alike. Prints the machine, its load, the medians, their ratio
# and whether the targets are met:
#   a calibrated sensor, or the calibrated wheels (row actuator: the shipped drive diagnosis's
#   speed_limit and slip on), costs at most 5 % more than the plug-in's implementation (ratio <= 1.05);
#   so do the calibrated proximity and light sensors with a diagnosis's effects on (rows
#   proximity-effects and light-effects: every effect of the kind ARGoS applies, from
#   bench/argos_effects.json; the proximity's long tail of 300 counts over 20 mm makes its rays
#   0.13 m long);
#   so do the other calibrated parts with every effect of their kind ARGoS applies on (issue #20
#   item 8; bench/argos_effects.json over the shipped diagnoses): ground-effects (nonlinear_response),
#   tof-effects (tof_offset, tof_scale, latency), actuator-effects (the wheels with speed_limit,
#   accel_limit, speed_scale, wheel_slip), drive-effects (those wheels, and the calibrated encoders
#   and ToF reading them, against the plug-in's three), camera and camera-effects (the calibrated
#   camera with camera.json, then with radial distortion k1, k2, k3; the robots' cameras enabled),
#   battery-effects (a battery diagnosis's Cubic with its capacity_scale, corrected arithmetic);
#   the calibrated corrected Cubic battery (behaviour="corrected") costs no more than the
#   plug-in's Cubic (ratio <= 1.00).
# EPUCK2_BENCH_ARENA=walls puts every robot in a pen where its sensors see something all the time:
# its circle (radius 0.2385 m at 5 and 4 cm/s) runs between a cylinder of radius 0.17 m at the
# circle's centre and four walls 0.29 m from it, with four lights (LED medium) inside the pen's
# corners; the proximity rays hit the cylinder and the walls (incidence_angle's normal: radial and
# the face's), the ToF the walls, the light sensors and the camera see the lights. Default: open
# (robots 2 m apart in an empty arena, which mostly measures a sensor seeing nothing).
# Noise is off on both sides (the plug-in's noise_level 0, the calibrated noise="false"): the
# rows compare the models, not the random number draws.
# EPUCK2_BENCH_MEASURE=instructions counts the instructions argos3 executes instead (valgrind
# --tool=callgrind, about 50 times slower; deterministic, so one repeat says it): where the CPU
# times' run-to-run noise is larger than the difference, the counts decide. Its last two columns
# are the instructions of the sensor's Update or the discharge model alone (inclusive), default
# and calibrated, in millions.
#   usage: bench/argos_cost.sh [SIM_SECONDS (default 7200)] [REPEATS (default 3)] [ROBOTS (default "1 10 50")] [ROWS]
#     ROWS: a space-separated subset of: proximity proximity-effects ground ground-effects tof tof-effects encoder light
#           light-effects camera camera-effects actuator actuator-effects drive-effects battery-simple battery-linear
#           battery-cubic battery-approximated battery-cubic-corrected battery-effects (default: all)
# Environment: EPUCK2_BUILD_DIR (default build), EPUCK2_BENCH_MEASURE (cpu, default, or instructions),
# EPUCK2_BENCH_ARENA (open, default, or walls).
# Needs ARGoS, the E-Puck2 plug-in and the project built with them (build/lib/argos3), python3.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SECONDS_SIM="${1:-7200}"; REPEATS="${2:-3}"; ROBOTS="${3:-1 10 50}"
ROWS="${4:-proximity proximity-effects ground ground-effects tof tof-effects encoder light light-effects camera camera-effects actuator actuator-effects drive-effects battery-simple battery-linear battery-cubic battery-approximated battery-cubic-corrected battery-effects}"
ARENA="${EPUCK2_BENCH_ARENA:-open}"
case "$ARENA" in open|walls) ;; *) echo "argos_cost: EPUCK2_BENCH_ARENA must be open or walls" >&2; exit 2;; esac
LIBDIR="${EPUCK2_BUILD_DIR:-$ROOT/build}/lib/argos3"
command -v argos3 >/dev/null || { echo "argos_cost: argos3 not found (docs/argos.md)" >&2; exit 3; }
command -v python3 >/dev/null || { echo "argos_cost: python3 not found" >&2; exit 3; }
[ -e "$LIBDIR/libepuck2_argos_calibrated.so" ] || { echo "argos_cost: build the project with ARGoS first" >&2; exit 3; }
LIBDIR="$(cd "$LIBDIR" && pwd)"
WORK="$(mktemp -d)"; trap 'rm -rf "$WORK"' EXIT
F="$ROOT/data/fitted"
# The shipped diagnoses with every effect of their kind ARGoS applies switched on (bench/argos_effects.json).
python3 - "$F" "$WORK" "$ROOT/bench/argos_effects.json" <<'PY'
import json, sys
f, work, effects = sys.argv[1], sys.argv[2], json.load(open(sys.argv[3]))
for kind in ("proximity", "light", "ground", "drive", "camera", "battery"):
    d = json.load(open(f"{f}/reports/diagnose_{kind}.json"))
    d["effects"] = effects[kind]
    d.setdefault("parameters", {}).update(effects.get(f"{kind}_parameters", {}))
    json.dump(d, open(f"{work}/{kind}_effects.json", "w"))
PY

# sensor XML for (what, impl)
sensor_xml() {
  local what="$1" impl="$2" c=""
  [ "$impl" = calibrated ] && c=" noise=\"false\""
  case "$what" in
    proximity) [ "$impl" = calibrated ] && c+=" coefficients=\"$F/proximity.json\""; echo "<epuck2_proximity implementation=\"$impl\"$c/>";;
    proximity-effects) [ "$impl" = calibrated ] && c+=" coefficients=\"$WORK/proximity_effects.json\""; echo "<epuck2_proximity implementation=\"$impl\"$c/>";;
    light-effects) [ "$impl" = calibrated ] && c+=" coefficients=\"$WORK/light_effects.json\""; echo "<epuck2_light implementation=\"$impl\"$c/>";;
    ground) [ "$impl" = calibrated ] && c+=" coefficients=\"$F/ground.json\"" || impl=rot_z_only; echo "<epuck2_ground implementation=\"$impl\"$c/>";;
    tof) [ "$impl" = calibrated ] && c+=" coefficients=\"$F/drive.json\""; echo "<epuck2_tof implementation=\"$impl\"$c/>";;
    encoder) [ "$impl" = calibrated ] && c+=" coefficients=\"$F/drive.json\""; echo "<epuck2_encoder implementation=\"$impl\"$c/>";;
    light) [ "$impl" = calibrated ] && c+=" coefficients=\"$F/light.json\""; echo "<epuck2_light implementation=\"$impl\"$c/>";;
    ground-effects) [ "$impl" = calibrated ] && c+=" coefficients=\"$WORK/ground_effects.json\"" || impl=rot_z_only; echo "<epuck2_ground implementation=\"$impl\"$c/>";;
    tof-effects) [ "$impl" = calibrated ] && c+=" coefficients=\"$WORK/drive_effects.json\""; echo "<epuck2_tof implementation=\"$impl\"$c/>";;
    drive-effects) [ "$impl" = calibrated ] && c+=" coefficients=\"$WORK/drive_effects.json\""
                   echo "<epuck2_encoder implementation=\"$impl\"$c/><epuck2_tof implementation=\"$impl\"$c/>";;
    camera|camera-effects)
      if [ "$impl" = calibrated ]; then
        [ "$what" = camera ] && c+=" coefficients=\"$F/camera.json\"" || c+=" coefficients=\"$WORK/camera_effects.json\""
      fi
      echo "<epuck2_colored_blob_perspective_camera implementation=\"$impl\" medium=\"leds\"$c/>";;
    battery-*|actuator|actuator-effects) echo "<epuck2_battery implementation=\"default\"/>";;
  esac
}
# actuator XML for (what, impl): the actuator row compares the calibrated wheels, with the shipped
# drive diagnosis's effects on (its speed_limit and slip), with the default differential steering.
# Rows actuator-effects and drive-effects: the diagnosis with every drive effect ARGoS applies on.
actuator_xml() {
  if [ "$1" = actuator ] && [ "$2" = calibrated ]; then
    echo "<differential_steering implementation=\"calibrated\" coefficients=\"$F/reports/diagnose_drive.json\"/>"
  elif { [ "$1" = actuator-effects ] || [ "$1" = drive-effects ]; } && [ "$2" = calibrated ]; then
    echo "<differential_steering implementation=\"calibrated\" coefficients=\"$WORK/drive_effects.json\"/>"
  else
    echo "<differential_steering implementation=\"default\"/>"
  fi
}
# battery XML for (what, impl): battery-MODEL compares the calibrated model (behaviour="argos")
# with the plug-in's MODEL; battery-cubic-corrected the calibrated Cubic with behaviour="corrected"
# with the plug-in's Cubic.
battery_xml() {
  local what="$1" impl="$2" m="${1#battery-}" behaviour=argos
  case "$what" in battery-*) ;; *) return;; esac
  [ "$m" = cubic-corrected ] && { m=cubic; behaviour=corrected; }
  if [ "$m" = effects ]; then  # a battery diagnosis: its model (Cubic) and capacity_scale, corrected
    [ "$impl" = calibrated ] && echo "<epuck2_battery discharge_model=\"calibrated\" coefficients=\"$WORK/battery_effects.json\" behaviour=\"corrected\"/>" ||
      echo "<epuck2_battery discharge_model=\"cubic\"/>"
    return
  fi
  if [ "$impl" = calibrated ]; then
    echo "<epuck2_battery discharge_model=\"calibrated\" coefficients=\"$F/battery.json\" model=\"$m\" behaviour=\"$behaviour\"/>"
  else
    [ "$m" = approximated ] && m=approx
    echo "<epuck2_battery discharge_model=\"$m\"/>"
  fi
}
# EPUCK2_BENCH_ARENA=walls: robot i's pen, around the centre of its circle (x, y - 0.2385): the
# e-puck2 at 5 and 4 cm/s turns right on a circle of radius 0.053 / 2 * 9 = 0.2385 m (its
# interwheel distance 0.053 m); its body (radius 0.035 m) stays 0.029 m inside the walls and 0.034 m
# outside the cylinder, so it never touches them, and its rays reach both.
pen() {  # i x y
  awk -v i="$1" -v x="$2" -v y="$3" 'BEGIN {
    cy = y - 0.2385
    printf "    <cylinder id=\"c%d\" radius=\"0.17\" height=\"0.1\" movable=\"false\"><body position=\"%.4f,%.4f,0\" orientation=\"0,0,0\"/></cylinder>\n", i, x, cy
    split("1 0 -1 0", dx); split("0 1 0 -1", dy)
    for (k = 1; k <= 4; ++k)
      printf "    <box id=\"w%d_%d\" size=\"%s\" movable=\"false\"><body position=\"%.4f,%.4f,0\" orientation=\"0,0,0\"/></box>\n",
             i, k, (dx[k] != 0 ? "0.02,0.62,0.1" : "0.62,0.02,0.1"), x + 0.30 * dx[k], cy + 0.30 * dy[k]
    for (k = 0; k < 4; ++k)
      printf "    <light id=\"l%d_%d\" position=\"%.4f,%.4f,0.043\" orientation=\"0,0,0\" color=\"yellow\" intensity=\"1.0\" medium=\"leds\"/>\n",
             i, k, x + (k % 2 ? 0.25 : -0.25), cy + (k < 2 ? 0.25 : -0.25)
  }'
}
write_exp() {  # what impl n file
  local what="$1" impl="$2" n="$3"
  {
    cat <<XML
<?xml version="1.0" ?>
<argos-configuration>
  <framework><system threads="0"/><experiment length="$SECONDS_SIM" ticks_per_second="10" random_seed="1"/></framework>
  <controllers>
    <epuck2_recorder_controller id="c" library="libepuck2_argos_protocols">
      <actuators>$(actuator_xml "$what" "$impl")</actuators>
      <sensors>$(sensor_xml "$what" "$impl")</sensors>
      <params left="5" right="4"/>
    </epuck2_recorder_controller>
  </controllers>
  <arena size="20, 20, 1" center="0,0,0.5">
    <floor id="floor" source="loop_functions" pixels_per_meter="10"/>
    <light id="light" position="0,0,0.043" orientation="0,0,0" color="yellow" intensity="1.0" medium="leds"/>
XML
    for i in $(seq 0 $((n - 1))); do
      x=$(awk -v i="$i" 'BEGIN{printf "%.2f", -8 + 2*(i%8)}'); y=$(awk -v i="$i" 'BEGIN{printf "%.2f", -8 + 2*int(i/8)}')
      echo "    <e-puck2 id=\"ep$i\"><body position=\"$x,$y,0\" orientation=\"0,0,0\"/><controller config=\"c\"/>$(battery_xml "$what" "$impl")</e-puck2>"
      [ "$ARENA" = walls ] && pen "$i" "$x" "$y"
    done
    cat <<XML
  </arena>
  <loop_functions library="libepuck2_argos_protocols" label="epuck2_bench_floor"/>
  <physics_engines><dynamics2d id="dyn2d"/></physics_engines>
  <media><led id="leds"/></media>
  <visualization/>
</argos-configuration>
XML
  } > "$4"
}

# CPU seconds (user + sys, microsecond resolution, from wait4's rusage) of one argos3 run.
cat > "$WORK/cpu.py" <<'PY'
import os, sys
log = open(sys.argv[1], "wb")
pid = os.fork()
if pid == 0:
    os.dup2(log.fileno(), 1); os.dup2(log.fileno(), 2)
    os.execvp(sys.argv[2], sys.argv[2:])
_, status, ru = os.wait4(pid, 0)
if os.waitstatus_to_exitcode(status) != 0:
    sys.exit(1)
print(f"{ru.ru_utime + ru.ru_stime:.6f}")
PY
MEASURE="${EPUCK2_BENCH_MEASURE:-cpu}"
case "$MEASURE" in
  cpu) UNIT="CPU seconds (user + sys) of argos3";;
  instructions) command -v valgrind >/dev/null || { echo "argos_cost: valgrind not found" >&2; exit 3; }
                UNIT="instructions executed by argos3 (callgrind), in millions";;
  *) echo "argos_cost: EPUCK2_BENCH_MEASURE must be cpu or instructions" >&2; exit 2;;
esac
cpu_run() {  # experiment -> CPU seconds (or millions of instructions) on stdout
  if [ "$MEASURE" = instructions ]; then
    ARGOS_PLUGIN_PATH="$LIBDIR" valgrind --tool=callgrind --callgrind-out-file="$WORK/cg" argos3 -n -z -c "$1" \
      > "$WORK/log" 2>&1 || { echo "argos_cost: argos3 failed on $1:" >&2; tail -n 20 "$WORK/log" >&2; exit 1; }
    awk '/^summary:/ {printf "%.3f\n", $2 / 1e6}' "$WORK/cg"
    # The model alone: the sensor's Update() or the discharge model's operator()(), inclusive.
    callgrind_annotate --inclusive=yes --threshold=100 "$WORK/cg" 2>/dev/null > "$WORK/annotated" || true
    grep -E 'argos::C(EPuck2[A-Za-z]*(Sensor|Actuator)::Update\(\)|DifferentialSteeringDefaultActuator::Update\(\)|EPuck2[A-Za-z]*DischargeModel[A-Za-z]*::operator\(\)\(\)) ' "$WORK/annotated" |
      head -n1 | awk '{gsub(",", "", $1); printf "%.3f\n", $1 / 1e6}' > "$1.model" || true
    return
  fi
  ARGOS_PLUGIN_PATH="$LIBDIR" python3 "$WORK/cpu.py" "$WORK/log" argos3 -n -z -c "$1" ||
    { echo "argos_cost: argos3 failed on $1:" >&2; tail -n 20 "$WORK/log" >&2; exit 1; }
}
median() { sort -g | awk '{a[NR]=$1} END{print (NR%2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }
load1() { cut -d' ' -f1 /proc/loadavg; }

echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) logical cores"
echo "load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "argos3: $(argos3 -n --version 2>&1 | grep -m1 VERSION | sed 's/\x1b\[[0-9;]*m//g')"
echo "arena: $ARENA; simulated ${SECONDS_SIM} s at 10 ticks/s; $UNIT, median of $REPEATS runs each,"
echo "default and calibrated interleaved (ABBA); ratio = calibrated / default medians; pairs = range of the"
echo "per-repeat ratios; target: sensors <= 1.05, battery-cubic-corrected <= 1.00"
printf "%-24s %6s %10s %12s %7s %13s %6s %7s %s\n" what robots default calibrated ratio pairs target result load
for n in $ROBOTS; do
  for what in $ROWS; do
    write_exp "$what" default "$n" "$WORK/a.argos"
    write_exp "$what" calibrated "$n" "$WORK/b.argos"
    : > "$WORK/a.times"; : > "$WORK/b.times"; : > "$WORK/ratios"
    l0=$(load1)
    for r in $(seq "$REPEATS"); do
      if [ $((r % 2)) -eq 1 ]; then
        ta=$(cpu_run "$WORK/a.argos"); tb=$(cpu_run "$WORK/b.argos")
      else
        tb=$(cpu_run "$WORK/b.argos"); ta=$(cpu_run "$WORK/a.argos")
      fi
      echo "$ta" >> "$WORK/a.times"; echo "$tb" >> "$WORK/b.times"
      awk -v a="$ta" -v b="$tb" 'BEGIN{printf "%.4f\n", b / a}' >> "$WORK/ratios"
    done
    ma=$(median < "$WORK/a.times"); mb=$(median < "$WORK/b.times")
    lo=$(sort -g "$WORK/ratios" | head -n1); hi=$(sort -g "$WORK/ratios" | tail -n1)
    case "$what" in
      proximity|proximity-effects|ground|ground-effects|tof|tof-effects|encoder|light|light-effects|camera|camera-effects|\
      actuator|actuator-effects|drive-effects|battery-effects) target=1.05;;
      battery-cubic-corrected) target=1.00;;
      *) target=-;;
    esac
    ratio=$(awk -v a="$ma" -v b="$mb" 'BEGIN{printf "%.3f", b / a}')
    result="-"
    [ "$target" != - ] && result=$(awk -v r="$ratio" -v t="$target" 'BEGIN{print (r <= t) ? "pass" : "FAIL"}')
    printf "%-24s %6d %10.3f %12.3f %7s %13s %6s %7s %s" "$what" "$n" "$ma" "$mb" "$ratio" "$lo-$hi" "$target" "$result" \
      "$l0-$(load1)"
    [ "$MEASURE" = instructions ] && printf "  model %s / %s" "$(cat "$WORK/a.argos.model")" "$(cat "$WORK/b.argos.model")"
    printf "\n"
  done
done
echo "load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"
