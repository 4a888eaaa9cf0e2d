#!/usr/bin/env bash
# The calibrated discharge model with behaviour="argos" and the plug-in's own tables must give, in
# ARGoS, the same charges as the plug-in's own model, printed with 17 significant digits (every bit of the double), for all 16 speeds.
# Both runs integrate the robots' motion with one dynamics2d step per tick (EPUCK2_ARGOS_ITERATIONS=1;
# the experiment has 10): the same 16 robots spinning in place, the same ticks (10 a second until
# every battery is empty, ~197 000) and the same ~19 200 rows compared bit for bit, in ~1.2 s of
# ARGoS a run instead of ~9 s (its time was almost all the ten physics steps). The two sides see
# the same motion, so the comparison is as strict; what the finer steps change is only the spin-up
# (the first tick's speed, docs/argos.md), which both sides then see alike.
# With ARC (a number in [-1, 1)), each robot drives a circle instead, its left wheel at ARC times
# its right one's: it moves every tick, so both sides must take its displacement, not its rotation,
# as the speed (the plug-in substitutes the rotation only when the displacement is 0).
#   usage: battery_bitexact.sh MODEL PLUGIN_TABLES_WRITER ARGOS_LIBDIR WORK_DIR [ARC]
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
MODEL="$1"; WRITER="$2"; LIBDIR="$3"; WORK="$4/bitexact_$1${5:+_arc}"
if [ -n "${5:-}" ]; then export EPUCK2_ARGOS_BATTERY_ARC="$5"; fi
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
export EPUCK2_BUILD_DIR="$(dirname "$(dirname "$LIBDIR")")" EPUCK2_BATTERY_MODEL="$MODEL" EPUCK2_BATTERY_BEHAVIOUR=argos EPUCK2_ARGOS_CHARGE_DIGITS=17 EPUCK2_ARGOS_ITERATIONS=1
rm -rf "$WORK"; mkdir -p "$WORK"
"$WRITER" "$WORK/plugin_tables.json"
"$ROOT/scripts/argos-record.sh" battery default "$WORK/plugin"
"$ROOT/scripts/argos-record.sh" battery "$WORK/plugin_tables.json" "$WORK/calibrated"
n=0
for f in "$WORK"/plugin/*.csv; do
  cmp -s "$f" "$WORK/calibrated/$(basename "$f")" || { echo "DIFFERENT: $(basename "$f")"; diff "$f" "$WORK/calibrated/$(basename "$f")" | head -5; exit 1; }
  n=$((n + 1))
done
if [ -n "${5:-}" ]; then
  # The robots did drive circles: the discharge models saw speeds of the mean of the wheels' (not
  # the rotation's |right - left| / 2), which ARGoS's log states per robot.
  grep -q "driving a circle, left wheel" "$WORK/calibrated/"*_speed-15.csv || fail_arc=1
  [ -z "${fail_arc:-}" ] || { echo "FAIL: the logs do not say the robots drove circles"; exit 1; }
fi
echo "identical: $n logs ($MODEL, plug-in model against calibrated behaviour=argos with the plug-in's tables${5:+, robots on circles, left wheel $5 x right})"
