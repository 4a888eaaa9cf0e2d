#!/usr/bin/env bash
# What the calibrated ARGoS plug-in costs against the E-Puck2 plug-in's own implementations:
# N robots (1, 10, 50) driving in circles for a simulated time, each sensor alone and each
# battery model, calibrated against default; wall-clock medians over repeats and their ratio.
#   usage: bench/argos_cost.sh [SIM_SECONDS (default 7200)] [REPEATS (default 3)] [ROBOTS (default "1 10 50")]
# Needs ARGoS, the E-Puck2 plug-in and the project built with them (build/lib/argos3).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SECONDS_SIM="${1:-7200}"; REPEATS="${2:-3}"; ROBOTS="${3:-1 10 50}"
LIBDIR="${EPUCK2_BUILD_DIR:-$ROOT/build}/lib/argos3"
command -v argos3 >/dev/null || { echo "argos_cost: argos3 not found" >&2; exit 3; }
[ -e "$LIBDIR/libepuck2_argos_calibrated.so" ] || { echo "argos_cost: build the project with ARGoS first" >&2; exit 3; }
LIBDIR="$(cd "$LIBDIR" && pwd)"
WORK="$(mktemp -d)"; trap 'rm -rf "$WORK"' EXIT
F="$ROOT/data/fitted"

# sensor XML for (what, impl)
sensor_xml() {
  local what="$1" impl="$2" c=""
  case "$what" in
    proximity) [ "$impl" = calibrated ] && c=" coefficients=\"$F/proximity.json\""; echo "<epuck2_proximity implementation=\"$impl\"$c/>";;
    ground) [ "$impl" = calibrated ] && c=" coefficients=\"$F/ground.json\"" || impl=rot_z_only; echo "<epuck2_ground implementation=\"$impl\"$c/>";;
    tof) [ "$impl" = calibrated ] && c=" coefficients=\"$F/drive.json\""; echo "<epuck2_tof implementation=\"$impl\"$c/>";;
    encoder) [ "$impl" = calibrated ] && c=" coefficients=\"$F/drive.json\""; echo "<epuck2_encoder implementation=\"$impl\"$c/>";;
    light) [ "$impl" = calibrated ] && c=" coefficients=\"$F/light.json\""; echo "<epuck2_light implementation=\"$impl\"$c/>";;
    battery-*) echo "<epuck2_battery implementation=\"default\"/>";;
  esac
}
battery_xml() {
  local what="$1" impl="$2" m="${1#battery-}"
  case "$what" in battery-*) ;; *) return;; esac
  if [ "$impl" = calibrated ]; then
    echo "<epuck2_battery discharge_model=\"calibrated\" coefficients=\"$F/battery.json\" model=\"$m\" behaviour=\"argos\"/>"
  else
    [ "$m" = approximated ] && m=approx
    echo "<epuck2_battery discharge_model=\"$m\"/>"
  fi
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
      <actuators><differential_steering implementation="default"/></actuators>
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
median() { sort -g | awk '{a[NR]=$1} END{print (NR%2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }

echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) logical cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "argos3: $(argos3 -n --version 2>&1 | head -n1)"
echo "simulated time ${SECONDS_SIM} s at 10 ticks/s, median of $REPEATS runs (wall seconds)"
printf "%-22s %6s %12s %12s %8s\n" what robots default_s calibrated_s ratio
for n in $ROBOTS; do
  for what in proximity ground tof encoder light battery-simple battery-linear battery-cubic battery-approximated; do
    declare -A med=()
    for impl in default calibrated; do
      exp="$WORK/$what-$impl-$n.argos"; write_exp "$what" "$impl" "$n" "$exp"
      for r in $(seq "$REPEATS"); do
        s=$(date +%s.%N)
        ARGOS_PLUGIN_PATH="$LIBDIR" argos3 -n -z -c "$exp" > "$WORK/log" 2>&1 || { cat "$WORK/log" >&2; exit 1; }
        e=$(date +%s.%N); echo "$e - $s" | bc -l
      done > "$WORK/times"
      med[$impl]=$(median < "$WORK/times")
    done
    printf "%-22s %6d %12.3f %12.3f %8.3f\n" "$what" "$n" "${med[default]}" "${med[calibrated]}" \
      "$(echo "${med[calibrated]} / ${med[default]}" | bc -l)"
  done
done
