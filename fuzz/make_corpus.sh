#!/usr/bin/env bash
# Seed corpus for the fuzz targets: make_corpus.sh [SOURCE_DIR [OUT_DIR [LINES]]]
# (defaults: the checkout holding this script, its fuzz/corpus, 40 lines)
#   OUT_DIR/fuzz_parse_log/    the first LINES lines (default 40) of every log in data/raw, each
#                              prefixed with the byte the target reads as the kind (see
#                              fuzz_parse_log.cpp): one file recognised from its columns, one with
#                              the kind given
#   OUT_DIR/fuzz_coefficients/ every coefficient file in data/fitted, prefixed with the byte that
#                              selects its loader (see fuzz_coefficients.cpp)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
src="${1:-$here/..}"
out="${2:-$here/corpus}"
lines="${3:-40}"
mkdir -p "$out/fuzz_parse_log" "$out/fuzz_coefficients"
kinds=(battery proximity light ground camera drive)
for i in "${!kinds[@]}"; do
  kind="${kinds[$i]}"
  for f in "$src/data/raw/$kind"/*.csv; do
    [ -e "$f" ] || continue
    base="$(basename "$f" .csv)"
    # Byte 0 = recognise the kind; byte 1 + index = that kind (battery 1 ... drive 6).
    { printf '\x00'; head -n "$lines" "$f"; } > "$out/fuzz_parse_log/${kind}_${base}_auto"
    { printf "\\x0$((i + 1))"; head -n "$lines" "$f"; } > "$out/fuzz_parse_log/${kind}_${base}_kind"
  done
done
# Loaders: 0 proximity, 1 light, 2 ground, 3 camera, 4 drive, 5 battery.
loaders=(proximity light ground camera drive battery)
for i in "${!loaders[@]}"; do
  f="$src/data/fitted/${loaders[$i]}.json"
  [ -e "$f" ] || continue
  { printf "\\x0$i"; cat "$f"; } > "$out/fuzz_coefficients/${loaders[$i]}.json"
done
echo "make_corpus: $(ls "$out/fuzz_parse_log" | wc -l) logs, $(ls "$out/fuzz_coefficients" | wc -l) coefficient files in $out"
