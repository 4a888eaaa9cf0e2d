#!/usr/bin/env bash
# The calibrated battery from what a user has, in ARGoS (robots ep5 and ep6 spinning at 5 and 6
# cm/s until empty, behaviour="corrected", Cubic):
#   partial   a file with tables at 5, 10 and 13 cm/s only (at 5, the file's 15 cm/s table): ep5 lasts
#             the file's lifetime_s at 5 cm/s, ep6 the plug-in's published lifetime at 6 cm/s (each within 1 %);
#   capacity  tables="plugin" with a diagnosis's capacity_scale k = 0.8: both lifetimes x 0.8
#             against the same run with k = 1 (within 0.2 %: 10 s rows over ~10^4 s); tables="plugin"
#             with no file at all runs as that k = 1 file, row for row;
#   model     a file naming battery_model (a diagnosis's) and no model= in the XML: the same charges as
#             model="simple" in the XML, unlike the Cubic's; model="approx" as model="approximated";
#   refusals  a covariate effect in the file, tables=, behaviour= or model= misspelt, and tables="file"
#             without a file each stop ARGoS at Init with a message that names the cause.
# Expected values: the files' own numbers and lib/models' copy of the plug-in's published tables.
#   usage: battery_options.sh ARGOS_LIBDIR WORK_DIR
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
LIBDIR="$1"; WORK="$2/battery_options"
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
rm -rf "$WORK"; mkdir -p "$WORK"
export ARGOS_PLUGIN_PATH="$LIBDIR"
fail() { echo "FAIL: $*"; exit 1; }
python3 - "$ROOT/data/fitted/battery.json" "$WORK" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
# The table at 5 cm/s is the file's 15 cm/s one, relabelled: a lifetime far from the plug-in's at 5
# cm/s, so that which table ARGoS uses shows.
fast = dict(d["speeds"][15], speed_cm_s=5.0)
# The file's 13 cm/s table too: the plug-in's then fill a run of two speeds (11, 12) and single
# ones (14, 15), which Init writes as such, not as ranges (docs/argos.md).
d["speeds"] = [fast, d["speeds"][10], d["speeds"][13]]
json.dump(d, open(sys.argv[2] + "/partial.json", "w"))
d["effects"] = {"capacity_scale": {"k": 0.8}}
json.dump(d, open(sys.argv[2] + "/k08.json", "w"))
# A diagnosis's discharge model (docs/coefficient-files.md: `battery_model`): Simple, far from the
# Cubic that ARGoS takes when neither the XML nor the file names one.
d.pop("effects")
d["battery_model"] = "simple"
json.dump(d, open(sys.argv[2] + "/simple.json", "w"))
PY
experiment() {  # dir battery_attributes
  mkdir -p "$1"
  python3 - "$ROOT/argos/experiments/battery.argos" "$1" "$2" <<'PY'
import re, sys
src, out, attrs = sys.argv[1], sys.argv[2], sys.argv[3]
beh = "" if "behaviour=" in attrs else ' behaviour="corrected"'
x = open(src).read()
x = re.sub(r'output_dir="[^"]*"', f'output_dir="{out}"', x)
robots = re.findall(r'    <e-puck2 id="ep\d+">.*?</e-puck2>\n', x, re.S)
keep = [r for r in robots if 'id="ep5"' in r or 'id="ep6"' in r]
x = x.replace("".join(robots), "".join(keep))
x = re.sub(r'<epuck2_battery discharge_model="calibrated"[^>]*/>',
           f'<epuck2_battery discharge_model="calibrated" {attrs}{beh} start_charge="1.0" />', x)
# One dynamics2d step per tick (the experiment has 10): two robots spinning in place need no finer
# steps, and the ten were 90 % of ARGoS's time; the checks below compare lifetimes and charges,
# which the finer steps change only through the spin-up of the first tick.
x = x.replace('<dynamics2d id="dyn2d" />', '<dynamics2d id="dyn2d" iterations="1" />')
assert 'iterations="1"' in x
open(out + "/exp.argos", "w").write(x)
PY
  argos3 -n -z -c "$1/exp.argos" > "$1/log" 2>&1 || { cat "$1/log"; fail "argos3 ($1)"; }
}
refused() {  # dir battery_attributes expected_message (a grep pattern)
  local dir="$1" attrs="$2" want="$3"
  if ( experiment "$dir" "$attrs" ) > /dev/null 2>&1; then fail "ARGoS ran with $attrs"; fi
  grep -q -- "$want" "$dir/log" || { cat "$dir/log"; fail "no message '$want' for $attrs"; }
  echo "ok   refusal: $(grep -o -- "$want.*" "$dir/log" | head -1 | cut -c1-150)"
}
python3 - "$ROOT/data/fitted/battery.json" "$WORK/covariate.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d["effects"] = {"covariate:temperature_c": {"slope": 0.01, "centre": 25.0}}
json.dump(d, open(sys.argv[2], "w"), indent=1)
PY
refused "$WORK/covariate" "coefficients=\"$WORK/covariate.json\"" \
  "covariate.json:[0-9]*:[0-9]*: effects.covariate:temperature_c: the calibrated battery cannot apply it in ARGoS: it needs the log column 'temperature_c'"
refused "$WORK/tables" "coefficients=\"$WORK/partial.json\" tables=\"files\"" "tables must be 'file' .* or 'plugin' .*, not 'files'"
refused "$WORK/behaviour" "coefficients=\"$WORK/partial.json\" behaviour=\"corected\"" "behaviour must be 'argos' or 'corrected', not 'corected'"
refused "$WORK/nofile" "tables=\"file\"" "the attribute 'coefficients' is required"
refused "$WORK/model" "coefficients=\"$WORK/partial.json\" model=\"cubical\"" "model must be simple, linear, cubic or approximated, not 'cubical'"
experiment "$WORK/partial" "coefficients=\"$WORK/partial.json\" model=\"cubic\""
grep -q "fitted tables at 5, 10, 13 cm/s, the plug-in's at 0..4, 6..9, 11, 12, 14, 15 cm/s" "$WORK/partial/log" || { cat "$WORK/partial/log"; fail "Init does not say which tables are the file's"; }
echo "ok   Init: $(grep -o 'fitted tables at [^;]*' "$WORK/partial/log" | head -1)"
experiment "$WORK/k1" "coefficients=\"$WORK/partial.json\" tables=\"plugin\" model=\"cubic\""
experiment "$WORK/k08" "coefficients=\"$WORK/k08.json\" tables=\"plugin\" model=\"cubic\""
grep -q "capacity scale 0.8" "$WORK/k08/log" || { cat "$WORK/k08/log"; fail "Init does not say the capacity scale"; }
# tables="plugin" needs no file (docs/argos.md: the plug-in's tables with the file's capacity scale,
# k = 1 without one): it runs, says so, and reads as the same tables through a file with k = 1.
experiment "$WORK/plugin_nofile" "tables=\"plugin\" model=\"cubic\""
grep -q "calibrated battery: no file: the plug-in's tables at every speed; model cubic" "$WORK/plugin_nofile/log" ||
  { cat "$WORK/plugin_nofile/log"; fail "Init does not say: no file, the plug-in's tables"; }
for f in "$WORK"/k1/*.csv; do
  cmp -s "$f" "$WORK/plugin_nofile/$(basename "$f")" || fail "tables=\"plugin\" without a file does not run as with a file of k = 1: $(basename "$f")"
done
echo "ok   tables=\"plugin\" without coefficients= runs the plug-in's tables, row for row as with a file of k = 1"
# The file's battery_model is the model when the XML names none: the same charges, row for row, as
# the XML naming it, and not those of the Cubic (the model without either).
experiment "$WORK/file_model" "coefficients=\"$WORK/simple.json\""
experiment "$WORK/xml_simple" "coefficients=\"$WORK/partial.json\" model=\"simple\""
experiment "$WORK/xml_cubic" "coefficients=\"$WORK/partial.json\" model=\"cubic\""
grep -q "; model simple" "$WORK/file_model/log" || { cat "$WORK/file_model/log"; fail "Init does not say the file's model"; }
for f in "$WORK"/xml_simple/*.csv; do
  cmp -s "$f" "$WORK/file_model/$(basename "$f")" || fail "the file's battery_model does not run as model=\"simple\": $(basename "$f")"
  ! cmp -s "$f" "$WORK/xml_cubic/$(basename "$f")" || fail "model=\"simple\" and model=\"cubic\" give the same charges: the test cannot tell them apart"
done
echo "ok   a diagnosis's battery_model (simple) runs as the XML's model=\"simple\", row for row, and not as the Cubic"
# model="approx" is the Approximated model (docs/argos.md: `approx` accepted): the same charges, row
# for row, as model="approximated", and Init names it.
experiment "$WORK/xml_approx" "coefficients=\"$WORK/partial.json\" model=\"approx\""
experiment "$WORK/xml_approximated" "coefficients=\"$WORK/partial.json\" model=\"approximated\""
grep -q "; model approximated" "$WORK/xml_approx/log" || { cat "$WORK/xml_approx/log"; fail "Init does not say model approximated for model=\"approx\""; }
for f in "$WORK"/xml_approximated/*.csv; do
  cmp -s "$f" "$WORK/xml_approx/$(basename "$f")" || fail "model=\"approx\" does not run as model=\"approximated\": $(basename "$f")"
  ! cmp -s "$f" "$WORK/xml_cubic/$(basename "$f")" || fail "model=\"approximated\" and model=\"cubic\" give the same charges: the test cannot tell them apart"
done
echo "ok   model=\"approx\" runs as model=\"approximated\", row for row, and not as the Cubic"
EPUCK2_ROOT="$ROOT" python3 - "$WORK" "$WORK/partial.json" <<'PY' || fail "lifetimes"
import glob, json, os, sys
work, partial = sys.argv[1], json.load(open(sys.argv[2]))
# The plug-in's published lifetime at 6 cm/s: the 5th number of row 6 of the Cubic table q[16][5]
# in lib/models' copy of the plug-in's source tables, read from the header's text.
import re
hdr = open(os.path.join(os.environ["EPUCK2_ROOT"], "lib/models/include/epuck2/models/plugin_battery_tables.hpp")).read()
block = hdr[hdr.index("q[16][5]"):]
rows = re.findall(r"\{([^{}]+)\}", block)[:16]
want6 = float(rows[6].split(",")[4])
def lifetime(d, speed):
    path = glob.glob(os.path.join(work, d, f"*_speed-{speed:02d}.csv"))[0]
    return float([l for l in open(path) if l[0].isdigit()][-1].split(",")[0])
bad = 0
def check(ok, msg):
    global bad
    print(("ok   " if ok else "FAIL ") + msg)
    bad += not ok
want5 = next(s["lifetime_s"] for s in partial["speeds"] if s["speed_cm_s"] == 5)
got5 = lifetime("partial", 5)
check(abs(got5 - want5) <= 0.01 * want5, f"partial: ep5 lasts {got5:.0f} s on the file's table (lifetime_s {want5:.0f} s)")
got6 = lifetime("partial", 6)
check(abs(got6 - want6) <= 0.01 * want6, f"partial: ep6 lasts {got6:.0f} s on the plug-in's table (published {want6:.0f} s)")
for v in (5, 6):
    a, b = lifetime("k1", v), lifetime("k08", v)
    check(abs(b / a - 0.8) <= 0.002, f"capacity: at {v} cm/s capacity_scale 0.8 lasts {b:.0f} s against {a:.0f} s (x {b / a:.4f})")
sys.exit(1 if bad else 0)
PY
