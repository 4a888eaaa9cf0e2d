#!/usr/bin/env bash
# Records one of the paper's protocols in ARGoS, headless, and writes its logs in the project's
# CSV formats (the ones epuck2-fit reads).
#   usage: scripts/argos-record.sh KIND COEFFICIENT_FILE|default OUT_DIR
#     KIND               proximity | ground | light | drive | battery
#     COEFFICIENT_FILE   a coefficient file written by epuck2-fit (proximity.json, ground.json,
#                        light.json, drive.json for drive, battery.json): the `calibrated`
#                        implementations use it;
#     default            the E-Puck2 plug-in's own implementations (and its battery tables).
# Environment: EPUCK2_BUILD_DIR (default build), EPUCK2_ARGOS_ROBOT (the `# robot:` id, default
# argos-epuck2), EPUCK2_ARGOS_NOISE (true|false, default false: the noiseless model),
# EPUCK2_BATTERY_MODEL (simple|linear|cubic|approximated, default cubic), EPUCK2_BATTERY_BEHAVIOUR
# (argos|corrected, default argos), EPUCK2_ARGOS_SEED (default 124), EPUCK2_ARGOS_CHARGE_DIGITS
# (significant digits of the battery charge, default 6), EPUCK2_ARGOS_SAMPLES (readings per
# condition for proximity, ground and light; default: the experiment's).
# Needs ARGoS 3, the E-Puck2 ARGoS plug-in and the project built with them (build/lib/argos3).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [ $# -ne 3 ]; then
  sed -n '2,16p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
KIND="$1"; COEFF="$2"; OUT="$3"
case "$KIND" in proximity|ground|light|drive|battery) ;; *) echo "argos-record: unknown kind '$KIND'" >&2; exit 2;; esac
BUILD="${EPUCK2_BUILD_DIR:-$ROOT/build}"
LIBDIR="$(cd "$BUILD" 2>/dev/null && pwd)/lib/argos3"
command -v argos3 >/dev/null 2>&1 || { echo "argos-record: argos3 not found (see docs/argos.md)" >&2; exit 3; }
[ -e "$LIBDIR/libepuck2_argos_protocols.so" ] || {
  echo "argos-record: $LIBDIR/libepuck2_argos_protocols.so missing: build the project with ARGoS installed" >&2; exit 3; }
if [ "$COEFF" != default ]; then
  [ -r "$COEFF" ] || { echo "argos-record: cannot read $COEFF" >&2; exit 2; }
  COEFF="$(cd "$(dirname "$COEFF")" && pwd)/$(basename "$COEFF")"
fi
mkdir -p "$OUT"
OUT="$(cd "$OUT" && pwd)"
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
if [ -n "${EPUCK2_ARGOS_SAMPLES:-}" ]; then
  case "$EPUCK2_ARGOS_SAMPLES" in ''|*[!0-9]*) echo "argos-record: EPUCK2_ARGOS_SAMPLES must be a whole number" >&2; exit 2;; esac
  sed -i -e "s|samples=\"[^\"]*\"|samples=\"$EPUCK2_ARGOS_SAMPLES\"|" "$EXP"
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
  echo "argos-record: argos3 failed on $EXP:" >&2; tail -n 20 "$OUT/.$KIND.argos.log" >&2; exit 1; }
ls "$OUT"/*.csv >/dev/null 2>&1 || { echo "argos-record: no log written in $OUT" >&2; exit 1; }
echo "argos-record: $KIND ($([ "$COEFF" = default ] && echo "plug-in defaults" || echo "$COEFF")) -> $OUT"
