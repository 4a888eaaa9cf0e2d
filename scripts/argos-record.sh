#!/usr/bin/env bash
# Records one of the paper's protocols in ARGoS, headless, and writes its logs in the project's
# CSV formats (the ones epuck2-fit reads); with --like, replays a measured log instead.
#   usage: scripts/argos-record.sh KIND COEFFICIENT_FILE|default OUT_DIR
#          scripts/argos-record.sh KIND COEFFICIENT_FILE|default OUT_LOG --like LOG
#     --like LOG         replay a measured log: ARGoS set up as each row says, its readings
#                        written as one log in the log's format, row for row, into OUT_LOG
#                        (written whole or not at all). drive: the robot at the log's
#                        obstacle_distance_m, its wheel commands row by row at 1000 ticks/s (each
#                        row read at the tick nearest its time); proximity: the row's sensor on a
#                        wall at distance_m (angle_deg off its normal); ground: the floor at grey
#                        (8-bit); light: a light on the sensor's axis at distance_m, of intensity;
#                        camera: an LED at forward_m, lateral_m, vertical_m; battery: spinning in
#                        place at speed_cm_s, the charge read at each row's time (a voltage_v
#                        column is left out: ARGoS has no voltage). A column ARGoS cannot set
#                        (e.g. temperature_c) stops the replay naming it (exit 2). Prints, per
#                        reading column, ARGoS against the log: MSE, mean and median |difference|;
#     KIND               proximity | ground | light | camera | drive | battery
#     COEFFICIENT_FILE   a coefficient file written by epuck2-fit (proximity.json, ground.json,
#                        light.json, camera.json, drive.json for drive, battery.json): the `calibrated`
#                        implementations use it;
#     default            the E-Puck2 plug-in's own implementations (and its battery tables).
# Environment: EPUCK2_BUILD_DIR (default build), EPUCK2_ARGOS_ROBOT (the `# robot:` id, default
# argos-epuck2), EPUCK2_ARGOS_NOISE (true|false, default false: the noiseless model),
# EPUCK2_ARGOS_NOISE_DISTRIBUTION (gaussian|uniform, default gaussian: the calibrated sensors'
# noise_distribution; uniform is the plug-in's uniform noise of the file's sd),
# EPUCK2_BATTERY_MODEL (simple|linear|cubic|approximated, default cubic), EPUCK2_BATTERY_BEHAVIOUR
# (argos|corrected, default argos), EPUCK2_ARGOS_SEED (default 124), EPUCK2_ARGOS_CHARGE_DIGITS
# (significant digits of the battery charge, default 6), EPUCK2_ARGOS_SAMPLES (readings per
# condition for proximity, ground and light; default: the experiment's), EPUCK2_ARGOS_FIRMWARE_CAP
# (true|false, default true: the calibrated wheels capped at the e-puck2 firmware's 1100 steps/s;
# false for logs of a robot without it, e.g. the project's generated logs), EPUCK2_ARGOS_ITERATIONS
# (dynamics2d's physics steps per tick, a whole number; default: the experiment's, 10; the battery's
# bit-exactness test uses 1: robots spinning in place need no finer steps, and ARGoS's time is
# almost all in them), EPUCK2_ARGOS_BATTERY_ARC (battery: the left wheel at this fraction of the
# right's, in [-1, 1), each robot on a circle; default -1, spinning in place).
# Needs ARGoS 3, the E-Puck2 ARGoS plug-in and the project's plug-in built (scripts/build.sh --argos: build/lib/argos3).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
LIKE=""
if [ $# -eq 5 ] && [ "$4" = "--like" ]; then LIKE="$5"; set -- "$1" "$2" "$3"; fi
if [ $# -ne 3 ]; then
  sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | grep -v '^set -euo' | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
KIND="$1"; COEFF="$2"; OUT="$3"
if [ -n "$LIKE" ]; then
  [ -r "$LIKE" ] || { echo "argos-record: cannot read $LIKE" >&2; exit 2; }
  LIKE="$(cd "$(dirname "$LIKE")" && pwd)/$(basename "$LIKE")"
fi
case "$KIND" in proximity|ground|light|camera|drive|battery) ;; *) echo "argos-record: unknown kind '$KIND'" >&2; exit 2;; esac
BUILD="${EPUCK2_BUILD_DIR:-$ROOT/build}"
LIBDIR="$(cd "$BUILD" 2>/dev/null && pwd)/lib/argos3"
command -v argos3 >/dev/null 2>&1 || { echo "argos-record: argos3 not found (see docs/argos.md)" >&2; exit 3; }
[ -e "$LIBDIR/libepuck2_argos_protocols.so" ] || {
  echo "argos-record: $LIBDIR/libepuck2_argos_protocols.so missing: build the plug-in (scripts/build.sh --argos) with ARGoS installed" >&2; exit 3; }
if [ "$COEFF" != default ]; then
  [ -r "$COEFF" ] || { echo "argos-record: cannot read $COEFF" >&2; exit 2; }
  COEFF="$(cd "$(dirname "$COEFF")" && pwd)/$(basename "$COEFF")"
fi
if [ -n "$LIKE" ]; then
  LIKE_OUT="$(cd "$(dirname "$OUT")" 2>/dev/null && pwd)/$(basename "$OUT")" || { echo "argos-record: no directory for $OUT" >&2; exit 2; }
  OUT="$(mktemp -d "${TMPDIR:-/tmp}/argos-record.XXXXXX")"
  trap 'rm -rf "$OUT"' EXIT
else
  mkdir -p "$OUT"
  OUT="$(cd "$OUT" && pwd)"
fi
ROBOT="${EPUCK2_ARGOS_ROBOT:-argos-epuck2}"
NOISE="${EPUCK2_ARGOS_NOISE:-false}"
MODEL="${EPUCK2_BATTERY_MODEL:-cubic}"
BEHAVIOUR="${EPUCK2_BATTERY_BEHAVIOUR:-argos}"
SEED="${EPUCK2_ARGOS_SEED:-124}"

EXP="$OUT/.$KIND.argos"
sed -e "s|output_dir=\"[^\"]*\"|output_dir=\"$OUT\"|" \
    -e "s|robot=\"argos-epuck2\"|robot=\"$ROBOT\"|" \
    -e "s|random_seed=\"[^\"]*\"|random_seed=\"$SEED\"|" \
    -e "s|noise=\"false\"|noise=\"$NOISE\"|g" \
    -e "s|model=\"cubic\" behaviour=\"argos\"|model=\"$MODEL\" behaviour=\"$BEHAVIOUR\"|" \
    -e "s|charge_digits=\"6\"|charge_digits=\"${EPUCK2_ARGOS_CHARGE_DIGITS:-6}\"|" \
    "$ROOT/argos/experiments/$KIND.argos" > "$EXP"
if [ -n "$LIKE" ]; then
  sed -i -e "s|ticks_per_second=\"[^\"]*\"|ticks_per_second=\"1000\"|" \
         -e "s|kind=\"$KIND\"|kind=\"$KIND\" like=\"$LIKE\" like_out=\"$OUT/replay.csv\"|" "$EXP"
  # A camera log's LEDs may sit below the floor's plane (below the camera): the arena reaches 1 m under it.
  [ "$KIND" = camera ] && sed -i -e 's|<arena size="3, 3, 1" center="0,0,0.5">|<arena size="3, 3, 2" center="0,0,0">|' "$EXP"
  # Only the battery's 1000 ticks/s are too many: its runs last hours; 10 ticks/s as its protocol.
  if [ "$KIND" = battery ]; then
    sed -i -e "s|ticks_per_second=\"[^\"]*\"|ticks_per_second=\"10\"|" -e 's|length="[^"]*"|length="0"|' \
           -e '/<e-puck2 id="ep1">/,/<\/arena>/{/<\/arena>/!d}' "$EXP"
  fi
fi
if [ "${EPUCK2_ARGOS_FIRMWARE_CAP:-true}" = false ]; then
  sed -i -e 's|<differential_steering implementation="calibrated"|<differential_steering implementation="calibrated" firmware_cap="false"|' "$EXP"
fi
if [ -n "${EPUCK2_ARGOS_BATTERY_ARC:-}" ]; then
  [[ "$EPUCK2_ARGOS_BATTERY_ARC" =~ ^-?[0-9]+(\.[0-9]+)?$ ]] || { echo "argos-record: EPUCK2_ARGOS_BATTERY_ARC must be a number in [-1, 1)" >&2; exit 2; }
  sed -i -e "s|kind=\"battery\"|kind=\"battery\" arc=\"$EPUCK2_ARGOS_BATTERY_ARC\"|" "$EXP"
fi
if [ -n "${EPUCK2_ARGOS_ITERATIONS:-}" ]; then
  case "$EPUCK2_ARGOS_ITERATIONS" in ''|*[!0-9]*) echo "argos-record: EPUCK2_ARGOS_ITERATIONS must be a whole number above 0" >&2; exit 2;; esac
  [ "$((10#$EPUCK2_ARGOS_ITERATIONS))" -gt 0 ] || { echo "argos-record: EPUCK2_ARGOS_ITERATIONS must be a whole number above 0" >&2; exit 2; }
  sed -i -e "s|<dynamics2d id=\"dyn2d\"[^/]*/>|<dynamics2d id=\"dyn2d\" iterations=\"$EPUCK2_ARGOS_ITERATIONS\" />|" "$EXP"
fi
if [ -n "${EPUCK2_ARGOS_SAMPLES:-}" ]; then
  case "$EPUCK2_ARGOS_SAMPLES" in ''|*[!0-9]*) echo "argos-record: EPUCK2_ARGOS_SAMPLES must be a whole number" >&2; exit 2;; esac
  sed -i -e "s|samples=\"[^\"]*\"|samples=\"$EPUCK2_ARGOS_SAMPLES\"|" "$EXP"
fi
if [ -n "${EPUCK2_ARGOS_NOISE_DISTRIBUTION:-}" ]; then
  case "$EPUCK2_ARGOS_NOISE_DISTRIBUTION" in gaussian|uniform) ;; *)
    echo "argos-record: EPUCK2_ARGOS_NOISE_DISTRIBUTION must be gaussian or uniform, not '$EPUCK2_ARGOS_NOISE_DISTRIBUTION'" >&2; exit 2;; esac
  # The calibrated sensors' attribute (the plug-in's own implementations have none).
  if [ "$COEFF" != default ]; then
    sed -i -e "s|\(implementation=\"calibrated\".*\) noise=\"$NOISE\"|\1 noise=\"$NOISE\" noise_distribution=\"$EPUCK2_ARGOS_NOISE_DISTRIBUTION\"|" "$EXP"
  fi
fi
if [ "$COEFF" = default ]; then
  # The plug-in's implementations: rot_z_only for the ground sensors, default for the others;
  # its own discharge models (approx is its name for approximated).
  plugin_model="$MODEL"; [ "$MODEL" = approximated ] && plugin_model=approx
  sed -i -e 's|<epuck2_ground implementation="calibrated"|<epuck2_ground implementation="rot_z_only"|' \
         -e 's|implementation="calibrated"|implementation="default"|g' \
         -e "s|discharge_model=\"calibrated\"|discharge_model=\"$plugin_model\"|g" \
         -e 's| coefficients="[^"]*"||g' "$EXP"
else
  sed -i -e "s|coefficients=\"[^\"]*\"|coefficients=\"$COEFF\"|g" "$EXP"
fi
# Headless: the experiment files have an empty <visualization/>.
ARGOS_PLUGIN_PATH="$LIBDIR${ARGOS_PLUGIN_PATH:+:$ARGOS_PLUGIN_PATH}" argos3 -n -z -c "$EXP" > "$OUT/.$KIND.argos.log" 2>&1 || {
  # A log to replay that cannot be read is bad input (exit 2), said with its file and line.
  if [ -n "$LIKE" ] && grep -q "FATAL\] $LIKE" "$OUT/.$KIND.argos.log"; then
    grep "FATAL\] $LIKE" "$OUT/.$KIND.argos.log" | head -n1 | sed 's/^.*FATAL\] /argos-record: /' >&2; exit 2
  fi
  echo "argos-record: argos3 failed on $EXP:" >&2; tail -n 20 "$OUT/.$KIND.argos.log" >&2; exit 1; }
ls "$OUT"/*.csv >/dev/null 2>&1 || { echo "argos-record: no log written in $OUT" >&2; exit 1; }
if [ -n "$LIKE" ]; then
  # All or nothing: the loop functions rename the replay into place once they wrote all its rows.
  [ -e "$OUT/replay.csv" ] || { echo "argos-record: the replay of $LIKE was not completed" >&2; exit 1; }
  cp "$OUT/replay.csv" "$LIKE_OUT.tmp.$$" && mv -f "$LIKE_OUT.tmp.$$" "$LIKE_OUT"
  echo "argos-record: $LIKE replayed ($([ "$COEFF" = default ] && echo "plug-in defaults" || echo "$COEFF")) -> $LIKE_OUT"
  grep -h '\[epuck2_protocol\] replay:' "$OUT/.$KIND.argos.log" | sed 's/^.*\[epuck2_protocol\] replay: /argos-record: /' || true
  exit 0
fi
echo "argos-record: $KIND ($([ "$COEFF" = default ] && echo "plug-in defaults" || echo "$COEFF")) -> $OUT"
