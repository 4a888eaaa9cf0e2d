#!/usr/bin/env bash
# The README's second command: installs what is needed, builds everything (the tests and the
# benchmarks too: scripts/build.sh --all), and runs every test (CTest).
#   scripts/setup-and-test.sh             Release build in build/, all tests
#   scripts/setup-and-test.sh --sanitize  GCC AddressSanitizer + UndefinedBehaviorSanitizer (with
#                                         float-cast-overflow, which -fsanitize=undefined leaves out)
#                                         in build-sanitize/; any report aborts the test that hit it.
#                                         Slow: a full build plus the suite runs several times slower.
set -euo pipefail
cd "$(dirname "$0")/.."
SANITIZE=0
for arg in "$@"; do
  case "$arg" in
    --sanitize) SANITIZE=1 ;;
    -h|--help) sed -n '2,8p' "$0"; exit 0 ;;
    *) echo "setup-and-test: unknown option $arg" >&2; exit 2 ;;
  esac
done
JOBS="${EPUCK2_JOBS:-$(nproc 2>/dev/null || echo 2)}"
scripts/install-deps.sh
if [ "$SANITIZE" -eq 0 ]; then
  scripts/build.sh --all
  cd build
  ctest --output-on-failure -j"$JOBS"
  exit 0
fi

LAUNCHER=()
if command -v ccache >/dev/null 2>&1; then LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
SAN_FLAGS="-fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all -fno-omit-frame-pointer"
# RelWithDebInfo: -O2 keeps the suite's run time bearable, -g gives the reports file:line.
# The benchmarks are not tests; leaving them out saves a third of the build. The ARGoS plug-in is
# left out too: an instrumented plug-in cannot load into an uninstrumented argos3 (its suite reports
# itself skipped).
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DEPUCK2_BUILD_APPS=ON \
  -DEPUCK2_BUILD_BENCH=OFF \
  -DEPUCK2_BUILD_ARGOS=OFF \
  -DCMAKE_CXX_COMPILER="${CXX:-g++}" \
  -DCMAKE_CXX_FLAGS="$SAN_FLAGS" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined,float-cast-overflow" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined,float-cast-overflow" \
  "${LAUNCHER[@]}" >/dev/null
cmake --build build-sanitize -j"$JOBS"
cd build-sanitize
# halt_on_error/abort_on_error turn every report into a failing test; detect_leaks stays on.
export ASAN_OPTIONS="${ASAN_OPTIONS:-halt_on_error=1:abort_on_error=1:detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:abort_on_error=1:print_stacktrace=1}"
# The benchmarks (and with them the python side-by-side comparison, which measures timing that
# sanitizers distort) are not configured here; every test runs.
ctest --output-on-failure -j"$JOBS"
