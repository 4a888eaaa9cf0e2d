#!/usr/bin/env bash
# What each translation unit costs to compile: CPU seconds (user + system of the compiler, which
# other builds on the machine do not inflate as they do wall time) and peak memory, the total,
# and the subtotal of what scripts/build.sh builds (lib/, validation/, apps/: the target
# `product`) against the ARGoS plug-in and the tests, benchmarks and examples. Prints the machine
# and its load. A unity build's combined units are the sources .../Unity/unity_N_cxx.cxx of the
# build folder (--only 'Unity' picks them); -DEPUCK2_UNITY_BUILD=OFF times one file at a time.
#   bench/build_time.sh [--build-dir DIR] [--only REGEX] [--jobs N] [--top N] [-- CMAKE_ARGS...]
#     --build-dir DIR  configure here (default build-time/; never ccache: every unit is compiled)
#     --only REGEX     time only the sources whose path matches (e.g. 'apps/|lib/fit/')
#     --jobs N         compile N units at once (default 1; CPU seconds per unit barely move with N)
#     --top N          print the N costliest units (default: all)
#     CMAKE_ARGS       passed to the configure step (e.g. -DEPUCK2_PCH=ON)
# Every unit is compiled with the command CMake generates for it (compile_commands.json).
set -euo pipefail
cd "$(dirname "$0")/.."
DIR=build-time
ONLY=""
JOBS=1
TOP=0
CMAKE_ARGS=()
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) DIR="$2"; shift 2 ;;
    --only) ONLY="$2"; shift 2 ;;
    --jobs) JOBS="$2"; shift 2 ;;
    --top) TOP="$2"; shift 2 ;;
    --) shift; CMAKE_ARGS=("$@"); break ;;
    -h|--help) sed -n '2,13p' "$0"; exit 0 ;;
    *) echo "build_time: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
case "$JOBS$TOP" in *[!0-9]*) echo "build_time: --jobs and --top take a whole number" >&2; exit 2 ;; esac
cmake -S . -B "$DIR" -DCMAKE_BUILD_TYPE=Release -DCMAKE_EXPORT_COMPILE_COMMANDS=ON \
  -DCMAKE_CXX_COMPILER_LAUNCHER= "${CMAKE_ARGS[@]}" >/dev/null
# Precompiled headers (when a configuration uses them) are built before the units that use them.
if grep -q cmake_pch "$DIR/compile_commands.json"; then
  echo "build_time: precompiled headers are on; their own compilation is timed as units named cmake_pch" >&2
fi
exec /usr/bin/python3 - "$DIR" "$ONLY" "$JOBS" "$TOP" <<'EOF'
import json, os, re, resource, shlex, subprocess, sys, time
from concurrent.futures import ThreadPoolExecutor

build_dir, only, jobs, top = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
source = os.getcwd()
entries = json.load(open(os.path.join(build_dir, "compile_commands.json")))
if only:
    entries = [e for e in entries if re.search(only, os.path.relpath(e["file"], source))]
# Precompiled headers first: the units that use them need them.
entries.sort(key=lambda e: ("cmake_pch" not in e["file"], e["file"]))

def cpu_model():
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return "unknown CPU"

def compile_one(e):
    args = shlex.split(e["command"]) if "command" in e else e["arguments"]
    # Time the compiler alone: a wait4 per child gives its own CPU seconds and peak memory.
    start = time.monotonic()
    p = subprocess.Popen(args, cwd=e["directory"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, ru = os.wait4(p.pid, 0)
    p.returncode = os.waitstatus_to_exitcode(status)
    err = p.stderr.read().decode(errors="replace")
    p.stderr.close()
    if p.returncode != 0:
        sys.stderr.write(f"build_time: {e['file']} did not compile:\n{err}\n")
        sys.exit(1)
    # The target's folder in the build tree: tests/CMakeFiles/test_safe_runs.dir/... is a test's.
    output = args[args.index("-o") + 1] if "-o" in args else ""
    where = os.path.relpath(os.path.join(e["directory"], output), build_dir)
    return (os.path.relpath(e["file"], source), ru.ru_utime + ru.ru_stime, time.monotonic() - start, ru.ru_maxrss / 1024,
            where)

load_before = os.getloadavg()
wall0 = time.monotonic()
pch = [e for e in entries if "cmake_pch" in e["file"]]
rest = [e for e in entries if "cmake_pch" not in e["file"]]
results = [compile_one(e) for e in pch]
with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
    results += list(pool.map(compile_one, rest))
wall = time.monotonic() - wall0
load_after = os.getloadavg()

def group(where):
    # What scripts/build.sh builds (the target `product`): the libraries and the CLI, whose objects
    # land under lib/, validation/ and apps/ of the build tree (a unity build's combined units too);
    # argos/ holds the plug-in (scripts/build.sh --argos) and its tests.
    head = where.split("/", 1)[0]
    if head in ("lib", "validation", "apps"):
        return "product (scripts/build.sh)"
    if head == "argos" and "/test" not in where:
        return "ARGoS plug-in (scripts/build.sh --argos)"
    return "tests, benchmarks, examples (the test command adds them)"

compiler = subprocess.run([rest[0]["command"].split()[0] if rest and "command" in rest[0] else "c++", "--version"],
                          capture_output=True, text=True).stdout.splitlines()[:1] if rest else ["?"]
print(f"machine: {cpu_model()}, {os.cpu_count()} logical cores; compiler: {compiler[0] if compiler else '?'}")
print(f"load average (1 min) before {load_before[0]:.2f}, after {load_after[0]:.2f}; "
      f"{len(results)} units, {max(1, jobs)} at a time, {wall:.0f} s wall")
print(f"{'CPU s':>7} {'wall s':>7} {'peak MB':>8}  unit")
shown = sorted(results, key=lambda r: -r[1])
for path, cpu, w, mb, where in (shown[:top] if top > 0 else shown):
    target = where.split("/CMakeFiles/", 1)[-1].split(".dir/", 1)[0]
    print(f"{cpu:7.1f} {w:7.1f} {mb:8.0f}  {path} ({target})")
totals = {}
for path, cpu, _, _, where in results:
    totals[group(where)] = totals.get(group(where), 0.0) + cpu
for g in sorted(totals):
    print(f"{totals[g]:7.1f} CPU s  {g}")
print(f"{sum(r[1] for r in results):7.1f} CPU s  total")
EOF
