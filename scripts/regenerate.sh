#!/usr/bin/env bash
# One command from raw logs to everything in data/fitted: coefficient files (JSON), the generated
# C++ header, reports and plots. With --raw it first re-records data/raw with the virtual robot
# (seeded: the same bytes every time). Progress goes to standard error, one line per stage, when
# standard error is a terminal or with --progress (the diagnosis then shows its own as well).
#   scripts/regenerate.sh [--raw] [--progress]
set -euo pipefail
cd "$(dirname "$0")/.."
FIT=build/bin/epuck2-fit
[ -x "$FIT" ] || { echo "regenerate: $FIT is missing: run scripts/build.sh first" >&2; exit 2; }
raw=0
progress=0
[ -t 2 ] && progress=1
for arg in "$@"; do
  case "$arg" in
    --raw) raw=1 ;;
    --progress) progress=1 ;;
    *) echo "regenerate: unknown option '$arg' (expected --raw, --progress)" >&2; exit 2 ;;
  esac
done
progress_opt=()
[ "$progress" = 1 ] && progress_opt=(--progress)
# Stages: recording (with --raw), battery, table5, 5 sensors, 6 diagnoses, codegen.
stages=$((1 + 1 + 5 + 6 + 1 + raw))
stage=0
say() {  # say WHAT: "regenerate: [3/14] WHAT" on standard error when progress is on
  stage=$((stage + 1))
  [ "$progress" = 1 ] && echo "regenerate: [$stage/$stages] $1" >&2
  return 0
}
if [ "$raw" = 1 ]; then
  say "recording data/raw with the virtual robot"
  for kind in battery proximity light ground camera drive; do
    "$FIT" generate "$kind" --out-dir "data/raw/$kind" "${progress_opt[@]}"
  done
fi
mkdir -p data/fitted/reports data/fitted/plots data/fitted/include/epuck2/fitted
coefficient_files=()

# Battery: the four discharge models, the voltage->charge map, Table 5, figures.
say "fitting battery"
"$FIT" battery data/raw/battery/*.csv -o data/fitted/battery.json \
  --plot data/fitted/plots/battery_fits.png --plot-lifetime data/fitted/plots/battery_lifetime.png \
  --plot-charge-map data/fitted/plots/battery_charge_map.png \
  > data/fitted/reports/battery.txt
coefficient_files+=(data/fitted/battery.json)
say "table5"
"$FIT" table5 data/raw/battery/*.csv -o data/fitted/reports/table5.json > data/fitted/reports/table5.txt

# Sensors: one coefficient file, report and plot per kind.
for kind in proximity light ground camera drive; do
  say "fitting $kind"
  if ls data/raw/$kind/*.csv >/dev/null 2>&1; then
    "$FIT" "$kind" data/raw/$kind/*.csv -o "data/fitted/$kind.json" --plot "data/fitted/plots/$kind.png" \
      > "data/fitted/reports/$kind.txt"
    coefficient_files+=("data/fitted/$kind.json")
  fi
done

# Diagnosis of every kind's logs: what the plug-in's models get wrong on them, and why
# (battery: against the tables just fitted, not the ones compiled into this binary).
for kind in battery proximity light ground camera drive; do
  say "diagnosing $kind"
  if ls data/raw/$kind/*.csv >/dev/null 2>&1; then
    extra=()
    [ "$kind" = battery ] && extra=(--coefficients data/fitted/battery.json)
    "$FIT" diagnose "${extra[@]}" "${progress_opt[@]}" data/raw/$kind/*.csv -o "data/fitted/reports/diagnose_$kind.json" \
      --plot "data/fitted/plots/diagnose_$kind.png" > "data/fitted/reports/diagnose_$kind.txt"
  fi
done

# The header compiled into lib/models (a test checks it matches these files).
say "codegen"
"$FIT" codegen "${coefficient_files[@]}" -o data/fitted/include/epuck2/fitted/coefficients.hpp
echo "regenerate: data/fitted is up to date (reports in data/fitted/reports, plots in data/fitted/plots)" >&2
cat data/fitted/reports/table5.txt
