#!/usr/bin/env bash
# The calibrated camera in ARGoS against the projection written here (pinhole with the file's
# horizontal field of view: f = (W/2) / tan(fov/2); px = cx - f (l/x)(1 + k1 r^2), py = cy -
# f (v/x)(1 + k1 r^2), r^2 = (l/x)^2 + (v/x)^2; then rounded), on the camera protocol's grid
# (argos/experiments/camera.argos):
#   plain      the shipped camera.json, noise off: every blob at the rounded projection;
#   distortion a diagnosis-like file with radial_distortion k1 = -0.3 and the centre at 80.4, 60.7;
#   noise      noise.camera 1.5 px: the readings' sd about the sub-pixel projection is
#              sqrt(1.5^2 + 1/12) within 10 %;
#   turned     the plain file on a robot turned about z (yaw 180 and 90; the grid is in the camera's
#              frame): the same blobs as the plain run, every one at the rounded projection;
#   range      the file's parameters.range_m 0.25 (the entity's own is 1 m): no LED farther
#              forward than 0.25 m is seen, the nearer ones are;
#   refusal    a covariate effect stops ARGoS at Init naming it.
#   usage: camera.sh ARGOS_LIBDIR WORK_DIR
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
LIBDIR="$1"; WORK="$2/calibrated_camera"
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
rm -rf "$WORK"; mkdir -p "$WORK"
export ARGOS_PLUGIN_PATH="$LIBDIR"
fail() { echo "FAIL: $*"; exit 1; }
python3 - "$ROOT/data/fitted/camera.json" "$WORK" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d.pop("robots", None)  # one robot: no pooled-set warning
json.dump(d, open(sys.argv[2] + "/plain.json", "w"))
json.dump(d, open(sys.argv[2] + "/yaw180.json", "w"))
json.dump(d, open(sys.argv[2] + "/yaw90.json", "w"))
d["parameters"]["range_m"] = 0.25
json.dump(d, open(sys.argv[2] + "/range.json", "w"))
d["parameters"]["range_m"] = 1.0  # the shipped file's
d["parameters"].update({"cx_px": 80.4, "cy_px": 60.7})
d["effects"] = {"radial_distortion": {"k1": -0.3}}
json.dump(d, open(sys.argv[2] + "/distortion.json", "w"))
d["noise"]["camera"]["sd"] = 1.5
d["noise"]["camera"].pop("per_sensor_sd", None)
json.dump(d, open(sys.argv[2] + "/noise.json", "w"))
d["effects"] = {"covariate:temperature_c": {"slope": 0.1, "centre": 25}}
json.dump(d, open(sys.argv[2] + "/covariate.json", "w"))
PY
run() {  # name noise samples [yaw]
  local dir="$WORK/$1"; mkdir -p "$dir"
  sed -e "s|<body position=\"0,0,0\" orientation=\"0,0,0\" />|<body position=\"0,0,0\" orientation=\"${4:-0},0,0\" />|" \
      -e "s|output_dir=\"[^\"]*\"|output_dir=\"$dir\"|" -e "s|coefficients=\"[^\"]*\"|coefficients=\"$WORK/$1.json\"|" \
      -e "s|noise=\"false\"|noise=\"$2\"|" -e "s|samples=\"[^\"]*\"|samples=\"$3\"|" \
      "$ROOT/argos/experiments/camera.argos" > "$dir/exp.argos"
  argos3 -n -z -c "$dir/exp.argos" > "$dir/log" 2>&1
}
run plain false 1 || { cat "$WORK/plain/log"; fail "argos3 (plain)"; }
run yaw180 false 1 180 || { cat "$WORK/yaw180/log"; fail "argos3 (yaw 180)"; }
run yaw90 false 1 90 || { cat "$WORK/yaw90/log"; fail "argos3 (yaw 90)"; }
grep -q 'orientation="180,0,0"' "$WORK/yaw180/exp.argos" || fail "the yaw was not set"
run range false 1 || { cat "$WORK/range/log"; fail "argos3 (range)"; }
run distortion false 1 || { cat "$WORK/distortion/log"; fail "argos3 (distortion)"; }
run noise true 20 || { cat "$WORK/noise/log"; fail "argos3 (noise)"; }
if run covariate false 1; then fail "ARGoS ran with a covariate effect on the camera"; fi
grep -q "effects.covariate:temperature_c: the calibrated epuck2_colored_blob_perspective_camera cannot apply it in ARGoS: it needs the log column 'temperature_c'" "$WORK/covariate/log" ||
  { cat "$WORK/covariate/log"; fail "no message naming the covariate"; }
echo "ok   refusal: $(grep -o "effects.covariate:temperature_c: [^(]*" "$WORK/covariate/log" | head -1)"
python3 - "$WORK" <<'PY'
import json, math, statistics, sys
work = sys.argv[1]
bad = 0
def rows(name):
    return [tuple(map(float, l.split(","))) for l in open(f"{work}/{name}/camera_argos-epuck2.csv") if l[0].isdigit() or l[0] == "-"]
def mean(name, x, l, v):
    d = json.load(open(f"{work}/{name}.json"))
    p, k1 = d["parameters"], d.get("effects", {}).get("radial_distortion", {}).get("k1", 0.0)
    f = (160 / 2) / math.tan(math.radians(p["fov_deg"]) / 2)
    a, b = l / x, v / x
    s = 1 + k1 * (a * a + b * b)
    return p["cx_px"] - f * a * s, p["cy_px"] - f * b * s
for name in ("plain", "distortion"):
    r = rows(name)
    wrong = [row for row in r if (row[3], row[4]) != tuple(float(round(m)) for m in mean(name, *row[:3]))]
    ok = r and not wrong
    print(("ok   " if ok else "FAIL ") + f"{name}: {len(r)} blobs, {len(wrong)} off the rounded projection" +
          (f" (first: {wrong[0]}, wanted {mean(name, *wrong[0][:3])})" if wrong else ""))
    bad += not ok
# A turned robot sees the grid as the plain one does (the LEDs are placed in the camera's frame).
for name in ("yaw180", "yaw90"):
    r, whole = rows(name), rows("plain")
    wrong = [row for row in r if (row[3], row[4]) != tuple(float(round(m)) for m in mean(name, *row[:3]))]
    ok = len(r) == len(whole) > 0 and not wrong
    print(("ok   " if ok else "FAIL ") + f"{name}: {len(r)} blobs (plain: {len(whole)}), {len(wrong)} off the rounded projection")
    bad += not ok
# The range: the grid runs 0.15-0.4 m forward; with range_m 0.25 the LEDs at 0.3 m and beyond are out
# of range, those at 0.15 and 0.2 m in (at most 0.2 m forward, 0.06 m aside and 0.03 m up: < 0.22 m away).
r, whole = rows("range"), rows("plain")
far = [row for row in r if row[0] > 0.25 + 1e-9]
near = [row for row in r if row[0] <= 0.2 + 1e-9]
near_plain = [row for row in whole if row[0] <= 0.2 + 1e-9]
ok = not far and len(near) == len(near_plain) > 0 and any(row[0] > 0.25 for row in whole)
print(("ok   " if ok else "FAIL ") + f"range: {len(r)} blobs with range_m 0.25 ({len(whole)} with the entity's 1 m), "
      f"{len(far)} beyond 0.25 m forward, {len(near)} of {len(near_plain)} at 0.2 m or nearer")
bad += not ok
r = rows("noise")
res = [row[3] - mean("noise", *row[:3])[0] for row in r] + [row[4] - mean("noise", *row[:3])[1] for row in r]
sd, want = statistics.pstdev(res), math.sqrt(1.5 ** 2 + 1 / 12)
ok = abs(sd - want) <= 0.1 * want
print(("ok   " if ok else "FAIL ") + f"noise: {len(res)} pixel coordinates scatter {sd:.3f} px about the projection "
      f"(noise.camera 1.5 px and the rounding: {want:.3f})")
bad += not ok
sys.exit(1 if bad else 0)
PY
