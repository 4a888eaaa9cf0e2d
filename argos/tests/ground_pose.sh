#!/usr/bin/env bash
# The calibrated ARGoS ground sensors sit where the robot's pose puts them: each sensor's offset in
# the robot's frame (the plug-in's (0.03, -0.009), (0.03, 0), (0.03, 0.009) m: right, centre,
# left) turned by the robot's yaw. The floor is black where x < 4.5 mm and white beyond
# (black_below_x, greys="1"); the robot stands at the origin; the file reads offset 60 + gain 900
# x grey, noise off. Expected, worked by hand (a yaw theta turns (x, y) into
# (x cos theta - y sin theta, ...); only the x matters):
#   yaw    0: x = 0.03, 0.03, 0.03        -> 960 960 960 (white, white, white)
#   yaw   90: x = 0.009, 0, -0.009        -> 960  60  60 (the right sensor over the white)
#   yaw  -90: x = -0.009, 0, 0.009        ->  60  60 960 (the left one)
#   yaw  180: x = -0.03, -0.03, -0.03     ->  60  60  60
#   usage: ground_pose.sh ARGOS_LIBDIR WORK_DIR
# Exit 77 (CTest: skipped) when argos3 is not installed.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
LIBDIR="$1"; WORK="$2/ground_pose"
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
rm -rf "$WORK"; mkdir -p "$WORK"
export ARGOS_PLUGIN_PATH="$LIBDIR"
python3 - "$ROOT/data/fitted/ground.json" "$WORK/inside.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
j.pop("robots", None)
j["parameters"]["gain"] = [900.0] * 3
j["parameters"]["offset"] = [60.0] * 3
json.dump(j, open(sys.argv[2], "w"), indent=1)
PY
bad=0
for pose in "0:960 960 960" "90:960 60 60" "-90:60 60 960" "180:60 60 60"; do
  yaw="${pose%%:*}"; want="${pose#*:}"
  dir="$WORK/yaw_$yaw"; mkdir -p "$dir"
  sed -e "s|output_dir=\"[^\"]*\"|output_dir=\"$dir\" black_below_x=\"0.0045\"|" \
      -e "s|coefficients=\"[^\"]*\"|coefficients=\"$WORK/inside.json\"|" \
      -e "s|greys=\"[^\"]*\"|greys=\"1\"|" -e "s|samples=\"[^\"]*\"|samples=\"3\"|" \
      -e "s|<body position=\"0,0,0\" orientation=\"0,0,0\" />|<body position=\"0,0,0\" orientation=\"$yaw,0,0\" />|" \
      "$ROOT/argos/experiments/ground.argos" > "$dir/exp.argos"
  grep -q "orientation=\"$yaw,0,0\"" "$dir/exp.argos" || { echo "FAIL: the pose was not set"; exit 1; }
  argos3 -n -z -c "$dir/exp.argos" > "$dir/log" 2>&1 || { cat "$dir/log"; echo "FAIL: argos3 (yaw $yaw)"; exit 1; }
  got=$(python3 - "$dir/ground_argos-epuck2.csv" <<'PY'
import sys
rows = [l.strip().split(",") for l in open(sys.argv[1]) if l[0].isdigit()]
per = {}
for g, s, v in rows:
    per.setdefault(int(s), set()).add(int(v))
# every sample of a sensor the same (noise off); one value per sensor, in sensor order
print(" ".join(str(sorted(per[k])[0]) if len(per[k]) == 1 else "varies" for k in sorted(per)))
PY
)
  if [ "$got" = "$want" ]; then echo "ok   yaw $yaw: $got"; else echo "FAIL yaw $yaw: read $got, want $want"; bad=1; fi
done
exit $bad
