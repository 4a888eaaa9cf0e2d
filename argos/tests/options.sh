#!/usr/bin/env bash
# The calibrated sensors' XML options in ARGoS: a robot's own coefficient set (robot="ID"), the
# Gaussian noise of the file's noise.<channel>.sd and its uniform alternative
# (noise_distribution="uniform"), a robot's own noise section where the top level has none, a file without a noise section (a warning, noise_level's uniform
# noise), noise_level beside a measured noise (ignored, with a warning), a noise section without the
# sensor's channel (a warning, no noise), a misspelt noise_distribution, and a bad coefficient file
# stopping ARGoS at Init with a message naming the file; curve="mean" (the means' curve), a curve
# that is neither, and a sensor without the coefficients attribute.
#   usage: options.sh ARGOS_LIBDIR WORK_DIR
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
LIBDIR="$1"; WORK="$2/options"
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
rm -rf "$WORK"; mkdir -p "$WORK"
export ARGOS_PLUGIN_PATH="$LIBDIR"
# A proximity file with a robot set and a reading noise of 41 counts; the same without a noise section.
python3 - "$ROOT/data/fitted/proximity.json" "$WORK/p.json" "$WORK/old.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d["robots"] = {"r1": {"parameters": {"a": 150.0, "b": -25.0, "c": 0.9}}}
d["noise"] = {"proximity": {"sd": 41.0, "unit": "counts", "from": "replicates", "n": 1000,
                            "argos_uniform_level": 3 ** 0.5 * 41.0 / 4095}}
json.dump(d, open(sys.argv[2], "w"))
d.pop("noise")
json.dump(d, open(sys.argv[3], "w"))
PY
experiment() {  # out_dir sensor_attributes distances samples
  sed -e "s|output_dir=\"[^\"]*\"|output_dir=\"$1\"|" \
      -e "s|coefficients=\"[^\"]*\" noise=\"false\"|$2|" \
      -e "s|distances=\"[^\"]*\"|distances=\"$3\"|" -e "s|samples=\"[^\"]*\"|samples=\"$4\"|" \
      "$ROOT/argos/experiments/proximity.argos" > "$1/exp.argos"
}
fail() { echo "FAIL: $*"; exit 1; }

# 1. robot="r1": 150 d^2 - 25 d + 0.9 at 20 mm, noiseless
mkdir -p "$WORK/robot"
experiment "$WORK/robot" "coefficients=\"$WORK/p.json\" robot=\"r1\" noise=\"false\"" "0.02:0.01:0.02" 5
argos3 -n -z -c "$WORK/robot/exp.argos" > "$WORK/robot/log" 2>&1 || { cat "$WORK/robot/log"; fail "argos3"; }
got=$(tail -n 1 "$WORK/robot/proximity_argos-epuck2.csv" | cut -d, -f4)
want=$(python3 -c "print(round((150*0.02**2 - 25*0.02 + 0.9)*4095))")
[ "$got" = "$want" ] || fail "robot r1 reads $got at 20 mm, expected $want"
echo "ok   robot=\"r1\": $got at 20 mm (the robot's set)"

# 1b. curve="mean": the file's curve of the means (mean_a d^2 + mean_b d + mean_c), not Eq. 1's
#     maxima; at 20 mm and 30 mm each curve read from the file by an independent reader, and the two
#     must differ there (else the case shows nothing). 1c: curve="maxima" is no curve: Init stops.
mkdir -p "$WORK/mean" "$WORK/badcurve"
experiment "$WORK/mean" "coefficients=\"$ROOT/data/fitted/proximity.json\" curve=\"mean\" noise=\"false\"" "0.02:0.01:0.03" 2
argos3 -n -z -c "$WORK/mean/exp.argos" > "$WORK/mean/log" 2>&1 || { cat "$WORK/mean/log"; fail "argos3 (curve=mean)"; }
python3 - "$ROOT/data/fitted/proximity.json" "$WORK/mean/proximity_argos-epuck2.csv" <<'PY' || fail "curve=\"mean\""
import json, sys
p = json.load(open(sys.argv[1]))["parameters"]
rows = [l.strip().split(",") for l in open(sys.argv[2]) if l[0].isdigit()]
ok = len(rows) > 0
for d in (0.02, 0.03):
    mean = round(min(max(p["mean_a"] * d * d + p["mean_b"] * d + p["mean_c"], 0), 1) * 4095)
    maxima = round(min(max(p["a"] * d * d + p["b"] * d + p["c"], 0), 1) * 4095)
    got = {int(r[3]) for r in rows if abs(float(r[1]) - d) < 1e-9 and r[2] == "0"}  # time_s,distance_m,sensor,value
    ok = ok and got == {mean} and mean != maxima
    print(("ok   " if got == {mean} and mean != maxima else "FAIL ") +
          f'curve="mean" at {d * 1000:.0f} mm: sensor 0 reads {sorted(got)}, the means\' curve {mean} (the maxima\'s {maxima})')
sys.exit(0 if ok else 1)
PY
experiment "$WORK/badcurve" "coefficients=\"$ROOT/data/fitted/proximity.json\" curve=\"maxima\" noise=\"false\"" "0.02:0.01:0.02" 1
if argos3 -n -z -c "$WORK/badcurve/exp.argos" > "$WORK/badcurve/log" 2>&1; then fail "argos3 ran with curve=\"maxima\""; fi
grep -q "calibrated epuck2_proximity: curve must be 'max' (Eq. 1 fitted to the maxima) or 'mean'" "$WORK/badcurve/log" ||
  { cat "$WORK/badcurve/log"; fail "no message naming the curve attribute"; }
echo "ok   curve=\"maxima\": stopped at Init naming the attribute"

# 2. noise="true" with noise.proximity.sd = 41 counts: a Gaussian of 41 counts; with
#    noise_distribution="uniform" the plug-in's uniform noise of the same variance (level
#    sqrt(3) 41 / 4095): the same sd, and no reading farther than sqrt(3) 41 = 71 counts (+1 for the
#    rounding) from the noiseless one, where a Gaussian of 400 draws has about 30.
sd_check() {  # csv label want_sd max_far min_far: readings beyond sqrt(3) sd + 1 from the median
  python3 - "$@" <<'PY' || fail "$2"
import statistics, sys
path, label, want = sys.argv[1], sys.argv[2], float(sys.argv[3])
v = [int(l.split(",")[3]) for l in open(path) if l[0].isdigit()]
sd = statistics.stdev(v)
ok = abs(sd - want) <= 0.1 * want
centre = statistics.median(v)
far = sum(abs(x - centre) > 3 ** 0.5 * want + 1 for x in v)
msg = f"{label}: {len(v)} readings, sd {sd:.1f} counts (file: {want:g}), {far} beyond sqrt(3) sd + 1"
ok = ok and int(sys.argv[5]) <= far <= int(sys.argv[4])
print(("ok   " if ok else "FAIL ") + msg)
sys.exit(0 if ok else 1)
PY
}
mkdir -p "$WORK/noise" "$WORK/uniform"
experiment "$WORK/noise" "coefficients=\"$WORK/p.json\" noise=\"true\"" "0.02:0.01:0.02" 400
argos3 -n -z -c "$WORK/noise/exp.argos" > "$WORK/noise/log" 2>&1 || { cat "$WORK/noise/log"; fail "argos3"; }
sd_check "$WORK/noise/proximity_argos-epuck2.csv" "gaussian noise" 41 400 10
experiment "$WORK/uniform" "coefficients=\"$WORK/p.json\" noise=\"true\" noise_distribution=\"uniform\"" "0.02:0.01:0.02" 400
argos3 -n -z -c "$WORK/uniform/exp.argos" > "$WORK/uniform/log" 2>&1 || { cat "$WORK/uniform/log"; fail "argos3"; }
sd_check "$WORK/uniform/proximity_argos-epuck2.csv" "uniform noise of the same variance" 41 0 0

# 2b. a file without a noise section: a warning at Init naming the file, and noise_level's uniform
#     noise (0 here: none)
mkdir -p "$WORK/old"
experiment "$WORK/old" "coefficients=\"$WORK/old.json\" noise=\"true\"" "0.02:0.01:0.02" 20
argos3 -n -z -c "$WORK/old/exp.argos" > "$WORK/old/log" 2>&1 || { cat "$WORK/old/log"; fail "argos3"; }
grep -q "calibrated epuck2_proximity: $WORK/old.json has no 'noise' section" "$WORK/old/log" ||
  { cat "$WORK/old/log"; fail "no warning about the missing noise section"; }
n=$(grep -c "has no 'noise' section" "$WORK/old/log")
[ "$n" = 1 ] || fail "the warning was printed $n times, expected once"
distinct=$(grep '^0' "$WORK/old/proximity_argos-epuck2.csv" | cut -d, -f4 | sort -u | wc -l)
[ "$distinct" = 1 ] || fail "noise_level 0 without a noise section should give no noise, found $distinct distinct readings"
echo "ok   no noise section: warned once, no noise with noise_level 0"

# 2c. noise_level given with a file that has the measured noise: a warning that it is ignored (the
#     readings keep the file's Gaussian of 41 counts); a noise section without this sensor's
#     channel: a warning and no noise at all; a misspelt noise_distribution: ARGoS stops at Init.
python3 - "$WORK/p.json" "$WORK/nochannel.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d["noise"] = {}  # a noise section, empty
json.dump(d, open(sys.argv[2], "w"))
PY
mkdir -p "$WORK/level" "$WORK/nochannel" "$WORK/distribution"
experiment "$WORK/level" "coefficients=\"$WORK/p.json\" noise=\"true\" noise_level=\"0.2\"" "0.02:0.01:0.02" 400
argos3 -n -z -c "$WORK/level/exp.argos" > "$WORK/level/log" 2>&1 || { cat "$WORK/level/log"; fail "argos3 (noise_level)"; }
grep -q "calibrated epuck2_proximity: noise_level is ignored: $WORK/p.json gives the measured reading noise (noise.proximity)" "$WORK/level/log" ||
  { cat "$WORK/level/log"; fail "no warning that noise_level is ignored"; }
sd_check "$WORK/level/proximity_argos-epuck2.csv" "noise_level ignored: the file's gaussian noise" 41 400 10
experiment "$WORK/nochannel" "coefficients=\"$WORK/nochannel.json\" noise=\"true\"" "0.02:0.01:0.02" 20
argos3 -n -z -c "$WORK/nochannel/exp.argos" > "$WORK/nochannel/log" 2>&1 || { cat "$WORK/nochannel/log"; fail "argos3 (no channel)"; }
grep -q "calibrated epuck2_proximity: $WORK/nochannel.json: the 'noise' section has no 'proximity' entry: this sensor draws no noise" "$WORK/nochannel/log" ||
  { cat "$WORK/nochannel/log"; fail "no warning about the missing noise channel"; }
distinct=$(grep '^0' "$WORK/nochannel/proximity_argos-epuck2.csv" | cut -d, -f4 | sort -u | wc -l)
[ "$distinct" = 1 ] || fail "a noise section without the proximity channel should give no noise, found $distinct distinct readings"
echo "ok   noise section without this channel: warned, no noise"
# 2d. a robot's own noise (docs/argos.md: a robot's set may hold its noise section): robot="r1"
#     whose set gives noise.proximity (sd 29 counts) where the file's top-level noise section has
#     no proximity entry: no "has no 'proximity' entry" warning, and a Gaussian of the robot's 29
#     counts.
python3 - "$WORK/p.json" "$WORK/robotnoise.json" <<'PY2'
import json, sys
d = json.load(open(sys.argv[1]))
d["noise"] = {}
d["robots"]["r1"]["noise"] = {"proximity": {"sd": 29.0, "unit": "counts", "from": "replicates", "n": 1000,
                                            "argos_uniform_level": 3 ** 0.5 * 29.0 / 4095}}
json.dump(d, open(sys.argv[2], "w"))
PY2
mkdir -p "$WORK/robotnoise"
experiment "$WORK/robotnoise" "coefficients=\"$WORK/robotnoise.json\" robot=\"r1\" noise=\"true\"" "0.02:0.01:0.02" 400
argos3 -n -z -c "$WORK/robotnoise/exp.argos" > "$WORK/robotnoise/log" 2>&1 || { cat "$WORK/robotnoise/log"; fail "argos3 (robot noise)"; }
if grep -q "has no 'proximity' entry" "$WORK/robotnoise/log"; then cat "$WORK/robotnoise/log"; fail "warned of a missing noise channel that robot r1's set gives"; fi
sd_check "$WORK/robotnoise/proximity_argos-epuck2.csv" "robot r1's own noise, none at the top level" 29 400 10
experiment "$WORK/distribution" "coefficients=\"$WORK/p.json\" noise=\"true\" noise_distribution=\"gauss\"" "0.02:0.01:0.02" 1
if argos3 -n -z -c "$WORK/distribution/exp.argos" > "$WORK/distribution/log" 2>&1; then fail "argos3 ran with noise_distribution=\"gauss\""; fi
grep -q "calibrated epuck2_proximity: noise_distribution must be 'gaussian' or 'uniform', not 'gauss'" "$WORK/distribution/log" ||
  { cat "$WORK/distribution/log"; fail "no message naming noise_distribution"; }
echo "ok   misspelt noise_distribution: $(grep -o "noise_distribution must be[^)]*" "$WORK/distribution/log" | head -1)"

# 3. a missing coefficient file stops ARGoS at Init, naming the sensor and the file
mkdir -p "$WORK/missing"
experiment "$WORK/missing" "coefficients=\"$WORK/nope.json\"" "0.02:0.01:0.02" 1
if argos3 -n -z -c "$WORK/missing/exp.argos" > "$WORK/missing/log" 2>&1; then fail "argos3 ran with a missing file"; fi
grep -q "calibrated epuck2_proximity: $WORK/nope.json: cannot open the file for reading" "$WORK/missing/log" ||
  { cat "$WORK/missing/log"; fail "no message naming the file"; }
echo "ok   missing file: $(grep -o 'calibrated epuck2_proximity: .*' "$WORK/missing/log")"

# 3b. no coefficients attribute at all: Init stops, saying the attribute is required
mkdir -p "$WORK/noattr"
experiment "$WORK/noattr" "noise=\"false\"" "0.02:0.01:0.02" 1
if argos3 -n -z -c "$WORK/noattr/exp.argos" > "$WORK/noattr/log" 2>&1; then fail "argos3 ran without a coefficients attribute"; fi
grep -q "calibrated epuck2_proximity: the attribute 'coefficients' is required" "$WORK/noattr/log" ||
  { cat "$WORK/noattr/log"; fail "no message naming the missing attribute"; }
echo "ok   no coefficients attribute: stopped at Init naming it"

# 4. a diagnosis file: its effects are applied (the shipped diagnosis: ambient_offset), so that at
#    20 mm the sensor reads 4095 clamp01(a d^2 + b d + c) + offset with the file's a, b, c and offset
mkdir -p "$WORK/effects"
experiment "$WORK/effects" "coefficients=\"$ROOT/data/fitted/reports/diagnose_proximity.json\" noise=\"false\"" "0.02:0.01:0.02" 1
argos3 -n -z -c "$WORK/effects/exp.argos" > "$WORK/effects/log" 2>&1 || { cat "$WORK/effects/log"; fail "argos3 with a diagnosis file"; }
got=$(tail -n 1 "$WORK/effects/proximity_argos-epuck2.csv" | cut -d, -f4)
want=$(python3 - "$ROOT/data/fitted/reports/diagnose_proximity.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
p, e = d["parameters"], d["effects"]
v = 4095 * min(max(p["a"] * 0.02 ** 2 + p["b"] * 0.02 + p["c"], 0), 1) + e["ambient_offset"]["offset"]
print(min(max(round(v), 0), 4095))
PY
)
[ "$got" = "$want" ] || fail "the diagnosis file reads $got at 20 mm, expected $want (its ambient_offset applied)"
echo "ok   diagnosis file: $got at 20 mm (the base curve with its ambient_offset)"
# 5. a file of the wrong kind: the drive file for the wheels given to the proximity sensor
mkdir -p "$WORK/kind"
experiment "$WORK/kind" "coefficients=\"$ROOT/data/fitted/drive.json\"" "0.02:0.01:0.02" 1
if argos3 -n -z -c "$WORK/kind/exp.argos" > "$WORK/kind/log" 2>&1; then fail "argos3 ran with a drive file on the proximity sensor"; fi
grep -q "calibrated epuck2_proximity: .*drive.json:[0-9]*:[0-9]*: is not a proximity coefficient file (kind \"drive\")" "$WORK/kind/log" ||
  { cat "$WORK/kind/log"; fail "no message naming the kind"; }
echo "ok   wrong kind: $(grep -o "is not a proximity coefficient file[^)]*)" "$WORK/kind/log" | head -1)"

# 6. the encoders' uniform noise (noise_distribution="uniform", docs/argos.md): the plug-in's, added
#    to the count on every tick a wheel turns and accumulating there, with the level of the file's
#    sd (a drive file with noise.encoder.sd 5 steps): recorded twice with the same seed, noiseless
#    and noisy, one row a tick, the difference noisy - noiseless (a) stays exactly as it was on
#    every row where the wheel stood still, (b) moves by increments of sd 5 steps (within 12 %;
#    the floor of both counts adds at most 1/3 step^2) on the rows where it turned -- a noise drawn
#    afresh on each reading in place of accumulated would give sqrt(2) 5 -- and (c) never by more
#    than sqrt(3) 5 + 1 steps in one tick (uniform: a Gaussian of 5 steps passes it about 1 in 20).
mkdir -p "$WORK/encoder/quiet" "$WORK/encoder/uniform"
python3 - "$ROOT/data/fitted/drive.json" "$WORK/encoder/d.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d.pop("robots", None)
d["noise"]["encoder"]["sd"] = 5.0
json.dump(d, open(sys.argv[2], "w"))
PY
for mode in quiet uniform; do
  if [ "$mode" = quiet ]; then attr='noise="false"'; else attr='noise="true" noise_distribution="uniform"'; fi
  sed -e "s|output_dir=\"[^\"]*\"|output_dir=\"$WORK/encoder/$mode\"|" \
      -e "s|coefficients=\"[^\"]*\"|coefficients=\"$WORK/encoder/d.json\"|g" -e "s|speeds=\"[^\"]*\"|speeds=\"2.5,5,7.5\"|" \
      -e "s|\(<epuck2_encoder implementation=\"calibrated\" coefficients=\"[^\"]*\"\) noise=\"false\"|\1 $attr|" \
      "$ROOT/argos/experiments/drive.argos" > "$WORK/encoder/$mode/exp.argos"
  grep -q "<epuck2_encoder implementation=\"calibrated\" coefficients=\"$WORK/encoder/d.json\" $attr" "$WORK/encoder/$mode/exp.argos" ||
    fail "the encoder's attributes were not set in $WORK/encoder/$mode/exp.argos"
  (cd "$WORK/encoder/$mode" && argos3 -n -z -c exp.argos > log 2>&1) || { cat "$WORK/encoder/$mode/log"; fail "argos3 (encoder, $mode)"; }
done
python3 - "$WORK/encoder/quiet" "$WORK/encoder/uniform" <<'PY' || fail "the encoders' uniform noise"
import glob, math, os, sys
quiet_dir, noisy_dir = sys.argv[1:3]
def rows(p):
    return [l.strip().split(",") for l in open(p) if l[0].isdigit()]
still_moved = 0; still = 0; steps = []
files = sorted(glob.glob(os.path.join(quiet_dir, "drive_*.csv")))
assert len(files) == 6, files
for q in files:
    rq, rn = rows(q), rows(os.path.join(noisy_dir, os.path.basename(q)))
    assert len(rq) == len(rn) > 10, q
    for col in (3, 4):  # left_steps, right_steps
        for i in range(1, len(rq)):
            dq = int(rq[i][col]) - int(rq[i - 1][col])
            dd = (int(rn[i][col]) - int(rq[i][col])) - (int(rn[i - 1][col]) - int(rq[i - 1][col]))
            if dq == 0:
                still += 1
                still_moved += dd != 0
            else:
                steps.append(dd)
n = len(steps); mean = sum(steps) / n
sd = math.sqrt(sum((x - mean) ** 2 for x in steps) / (n - 1))
far = sum(abs(x) > 3 ** 0.5 * 5 + 1 for x in steps)
ok = still > 50 and still_moved == 0 and n >= 300 and abs(sd - 5) <= 0.12 * 5 and far == 0
print(("ok   " if ok else "FAIL ") + f"encoder uniform noise: {still} still ticks, {still_moved} of them moved by the noise; "
      f"{n} turning ticks, increments sd {sd:.2f} steps (file 5), {far} beyond sqrt(3) 5 + 1")
sys.exit(0 if ok else 1)
PY

# 6b. the same uniform encoder noise on a robot pivoting on its still right wheel (the protocol's
#     right_wheel="0"): the left count moves and takes noise; the right count stays exactly at 0 on
#     every row, through the stop too -- the noise goes only to a wheel that turns, each wheel judged
#     by its own travel, and a stop after a turn moves neither wheel (before session 14's fix the
#     stop copied the left wheel's travel onto the right).
mkdir -p "$WORK/encoder/pivot"
sed -e "s|output_dir=\"[^\"]*\"|output_dir=\"$WORK/encoder/pivot\" right_wheel=\"0\"|" \
    -e "s|coefficients=\"[^\"]*\"|coefficients=\"$WORK/encoder/d.json\"|g" -e "s|speeds=\"[^\"]*\"|speeds=\"5\"|" \
    -e "s|\(<epuck2_encoder implementation=\"calibrated\" coefficients=\"[^\"]*\"\) noise=\"false\"|\1 noise=\"true\" noise_distribution=\"uniform\"|" \
    "$ROOT/argos/experiments/drive.argos" > "$WORK/encoder/pivot/exp.argos"
grep -q 'right_wheel="0"' "$WORK/encoder/pivot/exp.argos" || fail "right_wheel was not set in $WORK/encoder/pivot/exp.argos"
grep -q 'noise_distribution="uniform"' "$WORK/encoder/pivot/exp.argos" || fail "the encoder's noise was not set in $WORK/encoder/pivot/exp.argos"
(cd "$WORK/encoder/pivot" && argos3 -n -z -c exp.argos > log 2>&1) || { cat "$WORK/encoder/pivot/log"; fail "argos3 (encoder, pivot)"; }
python3 - "$WORK/encoder/pivot" <<'PY' || fail "the encoders on a pivoting robot"
import glob, os, sys
files = sorted(glob.glob(os.path.join(sys.argv[1], "drive_*.csv")))
assert len(files) == 2, files
rows = left_moves = right_cmd = 0; right_values = set()
for f in files:
    r = [l.strip().split(",") for l in open(f) if l[0].isdigit()]
    rows += len(r)
    right_cmd += sum(float(x[2]) != 0 for x in r)
    right_values |= {x[4] for x in r}
    left_moves += sum(r[i][3] != r[i - 1][3] for i in range(1, len(r)))
ok = rows > 100 and left_moves > 60 and right_cmd == 0 and right_values == {"0"}
print(("ok   " if ok else "FAIL ") + f"pivot on the right wheel, uniform encoder noise: {rows} rows, the left count moved on {left_moves}, "
      f"the right count read {sorted(right_values)} (must be only 0), right commands non-zero on {right_cmd} rows")
sys.exit(0 if ok else 1)
PY
