#!/usr/bin/env bash
# The calibrated ARGoS light sensors sit and look where the robot's pose puts them: each sensor's
# position in the robot's frame turned by the robot's yaw (the sensor's Update turns it by its
# anchor's orientation). The light protocol (a light on sensor 0's, then sensor 7's axis, at 0.1
# to 0.3 m) is run with the robot at yaws 0, 90, 180 and -90 degrees and the light placed on the
# turned axis (the loop functions' robot_yaw): the same geometry turned about z, so every reading
# must be the one at yaw 0 (noise off; a count of rounding allowed). A sensor position not turned
# moves the sensor by up to twice its 35 mm radius, which changes the readings by hundreds of counts
# at 0.1 m. The yaw-0 readings must also vary with the distance (not a rail), or the comparison
# shows nothing.
#   usage: light_pose.sh ARGOS_LIBDIR WORK_DIR
# Exit 77 (CTest: skipped) when argos3 is not installed.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
LIBDIR="$1"; WORK="$2/light_pose"
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
rm -rf "$WORK"; mkdir -p "$WORK"
export ARGOS_PLUGIN_PATH="$LIBDIR"
for yaw in 0 90 180 -90; do
  dir="$WORK/yaw_$yaw"; mkdir -p "$dir"
  sed -e "s|output_dir=\"[^\"]*\"|output_dir=\"$dir\" robot_yaw=\"$yaw\"|" \
      -e "s|coefficients=\"[^\"]*\"|coefficients=\"$ROOT/data/fitted/light.json\"|" \
      -e "s|distances=\"[^\"]*\"|distances=\"0.1:0.05:0.3\"|" -e "s|intensities=\"[^\"]*\"|intensities=\"1\"|" \
      -e "s|samples=\"[^\"]*\"|samples=\"2\"|" \
      "$ROOT/argos/experiments/light.argos" > "$dir/exp.argos"
  grep -q "robot_yaw=\"$yaw\"" "$dir/exp.argos" && grep -q 'noise="false"' "$dir/exp.argos" || { echo "FAIL: the yaw or the noise was not set"; exit 1; }
  argos3 -n -z -c "$dir/exp.argos" > "$dir/log" 2>&1 || { cat "$dir/log"; echo "FAIL: argos3 (yaw $yaw)"; exit 1; }
done
python3 - "$WORK" <<'PY'
import sys, glob, os
work = sys.argv[1]
def read(yaw):
    (path,) = glob.glob(f"{work}/yaw_{yaw}/light_intensity_*.csv")
    rows = [l.strip().split(",") for l in open(path) if l[0].isdigit()]
    return [(float(d), int(s), float(v)) for d, _, s, v in rows]
base = read(0)
values = sorted({v for _, _, v in base})
if len(base) < 16 or len(values) < 4 or max(values) >= 4095 or min(values) <= 0:
    sys.exit(f"FAIL: the yaw-0 run shows nothing: {len(base)} rows, values {values[:6]}...")
bad = 0
for yaw in (90, 180, -90):
    got = read(yaw)
    if [(d, s) for d, s, _ in got] != [(d, s) for d, s, _ in base]:
        print(f"FAIL yaw {yaw}: not the same rows as at yaw 0"); bad = 1; continue
    worst = max(abs(a[2] - b[2]) for a, b in zip(got, base))
    print(f"{'ok  ' if worst <= 1 else 'FAIL'} yaw {yaw}: {len(got)} readings, largest difference from yaw 0: {worst:g} counts")
    bad |= worst > 1
sys.exit(bad)
PY
