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
# The stages' commands are independent but for the battery's diagnosis (it reads battery.json) and
# codegen (every coefficient file): up to EPUCK2_JOBS of them (default: the cores) run at once,
# each writing only its own files, so the outputs are the same bytes whatever the order.
JOBS="${EPUCK2_JOBS:-$(nproc 2>/dev/null || echo 2)}"
running=()   # pids of the commands started and not yet waited for
failed=0
reap() {  # wait for one running command; remember a failure
  local pid=""
  wait -n -p pid "${running[@]}" || failed=1
  local keep=()
  for p in "${running[@]}"; do [ "$p" != "$pid" ] && keep+=("$p"); done
  running=("${keep[@]+"${keep[@]}"}")
}
start() {  # start OUT COMMAND...: the command in the background, its standard output into OUT
  local out="$1"; shift
  while [ "${#running[@]}" -ge "$JOBS" ]; do reap; done
  if [ "$out" = - ]; then "$@" & else "$@" > "$out" & fi
  running+=("$!")
}
finish() {  # wait for every command started; stop at the first stage that failed
  while [ "${#running[@]}" -gt 0 ]; do reap; done
  [ "$failed" = 0 ] || { echo "regenerate: a command above failed: data/fitted is incomplete" >&2; exit 1; }
}

say "fitting battery"
start data/fitted/reports/battery.txt "$FIT" battery data/raw/battery/*.csv -o data/fitted/battery.json \
  --plot data/fitted/plots/battery_fits.png --plot-lifetime data/fitted/plots/battery_lifetime.png \
  --plot-charge-map data/fitted/plots/battery_charge_map.png
coefficient_files+=(data/fitted/battery.json)
say "table5"
start data/fitted/reports/table5.txt "$FIT" table5 data/raw/battery/*.csv -o data/fitted/reports/table5.json

for kind in proximity light ground camera drive; do
  say "fitting $kind"
  if ls data/raw/$kind/*.csv >/dev/null 2>&1; then
    start "data/fitted/reports/$kind.txt" "$FIT" "$kind" data/raw/$kind/*.csv -o "data/fitted/$kind.json" \
      --plot "data/fitted/plots/$kind.png"
    coefficient_files+=("data/fitted/$kind.json")
  fi
done
finish  # the battery's diagnosis reads battery.json

for kind in drive battery proximity light ground camera; do
  say "diagnosing $kind"
  if ls data/raw/$kind/*.csv >/dev/null 2>&1; then
    extra=()
    [ "$kind" = battery ] && extra=(--coefficients data/fitted/battery.json)
    start "data/fitted/reports/diagnose_$kind.txt" "$FIT" diagnose "${extra[@]+"${extra[@]}"}" "${progress_opt[@]+"${progress_opt[@]}"}" \
      data/raw/$kind/*.csv -o "data/fitted/reports/diagnose_$kind.json" --plot "data/fitted/plots/diagnose_$kind.png"
  fi
done
finish

say "codegen"
"$FIT" codegen "${coefficient_files[@]}" -o data/fitted/include/epuck2/fitted/coefficients.hpp
echo "regenerate: data/fitted is up to date (reports in data/fitted/reports, plots in data/fitted/plots)" >&2
cat data/fitted/reports/table5.txt
