#!/usr/bin/env bash
# One command from raw logs to everything in data/fitted: coefficient files (JSON), the generated
# C++ header, reports and plots. With --raw it first re-records data/raw with the virtual robot
# (seeded: the same bytes every time).
#   scripts/regenerate.sh [--raw]
set -euo pipefail
cd "$(dirname "$0")/.."
FIT=build/bin/epuck2-fit
[ -x "$FIT" ] || { echo "regenerate: $FIT is missing: run scripts/build.sh first" >&2; exit 2; }
if [ "${1:-}" = "--raw" ]; then
  for kind in battery proximity light ground camera drive; do
    "$FIT" generate "$kind" --out-dir "data/raw/$kind"
  done
fi
mkdir -p data/fitted/reports data/fitted/plots data/fitted/include/epuck2/fitted
coefficient_files=()

# Battery: the four discharge models, Table 5, figures.
"$FIT" battery data/raw/battery/*.csv -o data/fitted/battery.json \
  --plot data/fitted/plots/battery_fits.png --plot-lifetime data/fitted/plots/battery_lifetime.png \
  > data/fitted/reports/battery.txt
coefficient_files+=(data/fitted/battery.json)
"$FIT" table5 data/raw/battery/*.csv -o data/fitted/reports/table5.json > data/fitted/reports/table5.txt

# Sensors: one coefficient file, report and plot per kind.
for kind in proximity light ground camera drive; do
  if ls data/raw/$kind/*.csv >/dev/null 2>&1; then
    "$FIT" "$kind" data/raw/$kind/*.csv -o "data/fitted/$kind.json" --plot "data/fitted/plots/$kind.png" \
      > "data/fitted/reports/$kind.txt"
    coefficient_files+=("data/fitted/$kind.json")
  fi
done

# Diagnosis of every kind's logs: what the plug-in's models get wrong on them, and why
# (battery: against the tables just fitted, not the ones compiled into this binary).
for kind in battery proximity light ground camera drive; do
  if ls data/raw/$kind/*.csv >/dev/null 2>&1; then
    extra=()
    [ "$kind" = battery ] && extra=(--coefficients data/fitted/battery.json)
    "$FIT" diagnose "${extra[@]}" data/raw/$kind/*.csv -o "data/fitted/reports/diagnose_$kind.json" \
      --plot "data/fitted/plots/diagnose_$kind.png" > "data/fitted/reports/diagnose_$kind.txt"
  fi
done

# The header compiled into lib/models (a test checks it matches these files).
"$FIT" codegen "${coefficient_files[@]}" -o data/fitted/include/epuck2/fitted/coefficients.hpp
echo "regenerate: data/fitted is up to date (reports in data/fitted/reports, plots in data/fitted/plots)" >&2
cat data/fitted/reports/table5.txt
