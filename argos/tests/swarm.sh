#!/usr/bin/env bash
# robot="auto" in ARGoS: five robots under one controller, a ground file with two robot sets
# (A: gain 900, offset 20; B: gain 600, offset 100), robot_map="ep0:A,ep1:A,ep*:B": ep0 and ep1
# must read A's offset + gain * grey, ep2..ep4 B's (worked here from the sets, noise off). Then
# the sets named like the entities (no robot_map), an entity without a set stopping ARGoS at Init
# with its name, the pooled set of a two-robot file without robot= warning at Init, and a
# diagnosis's nonlinear_response applied (the ground sensor reads its model through lib/coefficients).
#   usage: swarm.sh ARGOS_LIBDIR WORK_DIR
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
LIBDIR="$1"; WORK="$2/swarm"
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
rm -rf "$WORK"; mkdir -p "$WORK"
export ARGOS_PLUGIN_PATH="$LIBDIR"
fail() { echo "FAIL: $*"; exit 1; }
python3 - "$ROOT/data/fitted/ground.json" "$WORK" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
A = {"parameters": {"gain": [900.0] * 3, "offset": [20.0] * 3}}
B = {"parameters": {"gain": [600.0] * 3, "offset": [100.0] * 3}}
d["robots"] = {"A": A, "B": B}
json.dump(d, open(sys.argv[2] + "/sets.json", "w"))
d["robots"] = {f"ep{i}": (A if i < 2 else B) for i in range(5)}
json.dump(d, open(sys.argv[2] + "/named.json", "w"))
PY
experiment() {  # dir sensor_attributes
  mkdir -p "$1"
  python3 - "$ROOT/argos/experiments/ground.argos" "$1" "$2" <<'PY'
import re, sys
src, out, attrs = sys.argv[1], sys.argv[2], sys.argv[3]
x = open(src).read()
x = re.sub(r'output_dir="[^"]*"', f'output_dir="{out}"', x)
x = re.sub(r'greys="[^"]*"', 'greys="0,0.5,1"', x)
x = re.sub(r'samples="[^"]*"', 'samples="2"', x)
x = re.sub(r'coefficients="[^"]*" noise="false"', attrs + ' noise="false"', x)
robot = re.search(r'    <e-puck2 id="ep0">.*?</e-puck2>\n', x, re.S).group(0)
robots = "".join(robot.replace('id="ep0"', f'id="ep{i}"').replace('position="0,0,0"', f'position="{0.1 * i - 0.2},0.2,0"')
                 for i in range(5))
x = x.replace(robot, robots)
open(out + "/exp.argos", "w").write(x)
PY
}
check_sets() {  # dir
  python3 - "$1" <<'PY' || fail "robot=auto readings"
import glob, os, sys
d = sys.argv[1]
want = {"A": (900.0, 20.0), "B": (600.0, 100.0)}
bad = 0
for i in range(5):
    path = os.path.join(d, "ground_argos-epuck2.csv" if i == 0 else f"ground_ep{i}.csv")
    rows = [l.strip().split(",") for l in open(path) if l[0].isdigit()]
    g, o = want["A" if i < 2 else "B"]
    wrong = [r for r in rows if int(r[2]) != min(1023, max(0, round(o + g * float(r[0]))))]
    print(("ok   " if not wrong and rows else "FAIL ") + f"ep{i}: {len(rows)} readings, set {'A' if i < 2 else 'B'} "
          f"(grey {rows[-1][0]} reads {rows[-1][2]}, {round(o + g * float(rows[-1][0]))} wanted; {len(wrong)} wrong)")
    bad += bool(wrong) or not rows
sys.exit(1 if bad else 0)
PY
}
# 1. robot_map
experiment "$WORK/map" "coefficients=\"$WORK/sets.json\" robot=\"auto\" robot_map=\"ep0:A,ep1:A,ep*:B\""
argos3 -n -z -c "$WORK/map/exp.argos" > "$WORK/map/log" 2>&1 || { cat "$WORK/map/log"; fail "argos3 (robot_map)"; }
check_sets "$WORK/map"
# 2. sets named like the entities
experiment "$WORK/named" "coefficients=\"$WORK/named.json\" robot=\"auto\""
argos3 -n -z -c "$WORK/named/exp.argos" > "$WORK/named/log" 2>&1 || { cat "$WORK/named/log"; fail "argos3 (named)"; }
check_sets "$WORK/named"
# 3. an entity without a set: ARGoS stops at Init naming it
experiment "$WORK/missing" "coefficients=\"$WORK/sets.json\" robot=\"auto\""
if argos3 -n -z -c "$WORK/missing/exp.argos" > "$WORK/missing/log" 2>&1; then fail "robot=auto without a set for ep0 ran"; fi
grep -q "the entity 'ep0' has no robot set in the file (robots: A, B)" "$WORK/missing/log" || { cat "$WORK/missing/log"; fail "no message naming ep0"; }
echo "ok   robot=\"auto\" with no set for ep0 stops ARGoS at Init: $(grep -o "the entity 'ep0' has no robot set[^;]*" "$WORK/missing/log" | head -1)"
# 4. the pooled set of a multi-robot file without robot=: a warning naming the spread
experiment "$WORK/pooled" "coefficients=\"$ROOT/data/fitted/ground.json\""
argos3 -n -z -c "$WORK/pooled/exp.argos" > "$WORK/pooled/log" 2>&1 || { cat "$WORK/pooled/log"; fail "argos3 (pooled)"; }
grep -q "holds 2 robots (virtual-epuck2-1, virtual-epuck2-2) and no robot= is given: using the pooled set, which describes no robot; the robots differ beyond their uncertainties in gain\[0\]" "$WORK/pooled/log" \
  || { cat "$WORK/pooled/log"; fail "no pooled-set warning"; }
[ "$(grep -c 'using the pooled set' "$WORK/pooled/log")" = 1 ] || fail "the pooled-set warning is not said once"
echo "ok   a two-robot file without robot= warns once: $(grep -o 'holds 2 robots.*' "$WORK/pooled/log" | cut -c1-160)..."
# 5. a diagnosis's nonlinear_response (exponent 1.5) is applied: every robot reads offset + gain *
#    grey^1.5 per sensor (rounded), worked here from the file
python3 - "$ROOT/data/fitted/ground.json" "$WORK/nonlinear.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d.pop("robots", None)
d["effects"] = {"nonlinear_response": {"exponent": 1.5}}
json.dump(d, open(sys.argv[2], "w"))
PY
experiment "$WORK/nonlinear" "coefficients=\"$WORK/nonlinear.json\""
argos3 -n -z -c "$WORK/nonlinear/exp.argos" > "$WORK/nonlinear/log" 2>&1 || { cat "$WORK/nonlinear/log"; fail "argos3 (nonlinear)"; }
python3 - "$WORK" <<'PY' || fail "nonlinear_response"
import glob, json, sys
work = sys.argv[1]
p = json.load(open(f"{work}/nonlinear.json"))["parameters"]
n = wrong = 0
for path in glob.glob(f"{work}/nonlinear/ground_*.csv"):
    for l in open(path):
        if not l[0].isdigit():
            continue
        g, s, v = l.strip().split(",")
        g, s = float(g), int(s)
        want = min(1023, max(0, round(p["offset"][s] + p["gain"][s] * g ** 1.5)))
        n += 1
        wrong += int(v) != want
print(("ok   " if n and not wrong else "FAIL ") + f"nonlinear_response 1.5: {n} readings of 5 robots, {wrong} off offset + gain grey^1.5")
sys.exit(1 if wrong or not n else 0)
PY
