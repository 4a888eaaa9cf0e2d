#!/usr/bin/env python3
"""Fails when any object built outside lib/fit was compiled with a Ceres header, or when a target
outside lib/fit has Ceres' include folder on its include path: Ceres is linked PRIVATE to
epuck2_fit, and no public header of lib/fit includes it (epuck2::fit::Jet is lib/fit's own dual
number). It reads what the compiler itself recorded, after the build:

  - the dependency files of every object in the build tree: `*.o.d` (CMake's Makefile generator,
    GCC's -MD output), or `ninja -t deps` (the Ninja generator, which folds them into .ninja_deps);
    an object outside lib/fit's folder of the build tree (epuck2_fit, and lib/fit's own test of its
    Jet against Ceres') whose dependencies hold a `/ceres/` header fails, named with its target;
  - every target's include flags (`flags.make` under Makefiles, `INCLUDES` in build.ninja): a
    folder given with --ceres-include (Ceres' own include folders, less the compiler's implicit
    ones, which no flag names) or any folder with a `ceres` component fails outside lib/fit.

It also fails when it reads no dependency file at all (nothing built yet, or a format it does not
know): it cannot pass without having looked. tests/check_ceres_in_lib_fit.py reads the sources.

usage: check_ceres_objects.py BUILD_DIR GENERATOR MAKE_PROGRAM [--ceres-include DIR]...
       check_ceres_objects.py --self-test CMAKE GENERATOR MAKE_PROGRAM CERES_INCLUDE_DIR
         (builds a throwaway CMake project with that generator: a target that includes a Ceres
          header, one that puts a Ceres folder on its include path, one clean; the check must
          name the first two and pass the clean one, and must fail on an empty build tree)
"""
import os
import pathlib
import re
import shlex
import subprocess
import sys
import tempfile
import time

# lib/fit's folder of the build tree: epuck2_fit and lib/fit's own test program (Jet against Ceres').
ALLOWED_FOLDER = "lib/fit/CMakeFiles/"
TARGET_OF = re.compile(r"(?:^|/)CMakeFiles/([^/]+)\.dir/")


def allowed(path: str):
    return path.startswith(ALLOWED_FOLDER) or f"/{ALLOWED_FOLDER}" in path
CERES_HEADER = re.compile(r"/ceres/[^\s]*\.h")


def target_of(path: str):
    m = TARGET_OF.search(path)
    return m.group(1) if m else None


def makefile_deps(build: pathlib.Path):
    """(object, [dependencies]) from every GCC depfile CMake's Makefile generator left."""
    for d in sorted(build.rglob("*.o.d")):
        text = d.read_text(errors="replace").replace("\\\n", " ")
        _, _, rest = text.partition(": ")
        yield str(d.relative_to(build))[:-2], rest.split()


def ninja_deps(build: pathlib.Path, ninja: str):
    if not (build / "build.ninja").is_file():
        return
    out = subprocess.run([ninja, "-C", str(build), "-t", "deps"], capture_output=True, text=True, check=True).stdout
    obj, deps = None, []
    for line in out.splitlines():
        if line and not line[0].isspace():
            if obj is not None:
                yield obj, deps
            obj, deps = line.split(":")[0], []
        elif line.strip():
            deps.append(line.strip())
    if obj is not None:
        yield obj, deps


def include_flags(build: pathlib.Path, ninja_generator: bool):
    """(target's folder, target, include folder) for every include flag of every target."""
    def folders(flags: str):
        words = shlex.split(flags)
        i = 0
        while i < len(words):
            w = words[i]
            for opt in ("-isystem", "-iquote", "-idirafter", "-I"):
                if w == opt and i + 1 < len(words):
                    i += 1
                    yield words[i]
                    break
                if w.startswith(opt) and len(w) > len(opt):
                    yield w[len(opt):]
                    break
            i += 1

    if ninja_generator:
        if not (build / "build.ninja").is_file():
            return
        target = None
        for line in (build / "build.ninja").read_text(errors="replace").splitlines():
            if line.startswith("build "):
                obj = line[len("build "):].split(":")[0]
                target = target_of(obj)
            elif target and line.strip().startswith("INCLUDES = "):
                for f in folders(line.strip()[len("INCLUDES = "):]):
                    yield obj, target, f
    else:
        for flags in sorted(build.rglob("CMakeFiles/*.dir/flags.make")):
            rel = str(flags.relative_to(build))
            target = target_of(rel)
            for line in flags.read_text(errors="replace").splitlines():
                if line.startswith("CXX_INCLUDES = ") or line.startswith("C_INCLUDES = "):
                    for f in folders(line.split("=", 1)[1]):
                        yield rel, target, f


def out_of_date(build: pathlib.Path, obj: str, deps):
    """True when the object is missing or older than a dependency it recorded (a stale record)."""
    o = build / obj
    try:
        built = o.stat().st_mtime
    except OSError:
        return True
    # Relative paths in a record are relative to where the compiler ran: under Makefiles the
    # target's folder of the build tree (the part before CMakeFiles/), under Ninja the build tree.
    cwd = build / obj.split("CMakeFiles/")[0] if "CMakeFiles/" in obj else build
    for d in deps:
        p = pathlib.Path(d)
        if not p.is_absolute():
            p = cwd / p
        try:
            if p.stat().st_mtime > built:
                return True
        except OSError:
            continue  # a recorded file that is gone: the next build decides
    return False


def check(build: pathlib.Path, generator: str, make_program: str, ceres_includes):
    """Problems found (empty: clean), and how many objects were read."""
    ninja_generator = "Ninja" in generator
    records = list(ninja_deps(build, make_program) if ninja_generator else makefile_deps(build))
    problems = []
    if not records:
        problems.append(f"no dependency file read under {build} (generator {generator}): build first; "
                        "the check cannot pass without having read what the compiler included")
    checked = 0
    stale = []
    for obj, deps in records:
        target = target_of(obj)
        if allowed(obj):
            checked += 1
            continue
        if out_of_date(build, obj, deps):
            # An object older than one of its own recorded sources (a test program the default build
            # no longer makes, left by an earlier build): its record describes code that is not the
            # tree's any more, and the next build of its target recompiles it.
            stale.append(obj)
            continue
        checked += 1
        ceres = [d for d in deps if CERES_HEADER.search(d)]
        if ceres:
            problems.append(f"{obj} (target {target}) was compiled with {len(ceres)} Ceres header(s), e.g. {ceres[0]}")
    ceres_dirs = {str(pathlib.Path(c)) for c in ceres_includes}
    for where, target, folder in include_flags(build, ninja_generator):
        if allowed(where):
            continue
        norm = str(pathlib.Path(folder))
        if norm in ceres_dirs or "ceres" in pathlib.Path(folder).parts:
            problems.append(f"target {target} has Ceres' include folder {folder} on its include path")
    if records and not checked:
        problems.append(f"every one of the {len(records)} objects under {build} is older than its sources: build first")
    return sorted(set(problems)), checked, stale


def self_test(cmake: str, generator: str, make_program: str, ceres_include: str):
    with tempfile.TemporaryDirectory() as tmp:
        src, build = pathlib.Path(tmp) / "src", pathlib.Path(tmp) / "build"
        (src / "fake_ceres_root" / "include").mkdir(parents=True)
        src.joinpath("CMakeLists.txt").write_text(
            "cmake_minimum_required(VERSION 3.16)\nproject(planted CXX)\n"
            f"add_library(planted_header STATIC planted_header.cpp)\n"
            f"target_include_directories(planted_header PRIVATE {ceres_include})\n"
            "add_library(planted_path STATIC clean.cpp)\n"
            "target_include_directories(planted_path PRIVATE ${CMAKE_SOURCE_DIR}/fake_ceres_root/include)\n"
            "add_library(clean_target STATIC clean.cpp)\n"
            "add_subdirectory(lib/fit)\n")
        (src / "lib" / "fit").mkdir(parents=True)
        src.joinpath("lib", "fit", "CMakeLists.txt").write_text(
            "add_library(epuck2_fit STATIC ../../planted_header.cpp)\n"
            "target_include_directories(epuck2_fit PRIVATE ${CMAKE_SOURCE_DIR}/fake_ceres_root/include)\n")
        src.joinpath("planted_header.cpp").write_text("#include <ceres/version.h>\nint f() { return CERES_VERSION_MAJOR; }\n")
        src.joinpath("clean.cpp").write_text("#include <cmath>\ndouble g(double x) { return std::sqrt(x); }\n")
        build.mkdir()
        empty, n, _ = check(build, generator, make_program, [])
        failures = [] if (empty and n == 0 and "no dependency file" in empty[0]) else [f"an empty build tree passed: {empty}"]
        for step in ([cmake, "-S", str(src), "-B", str(build), "-G", generator, f"-DCMAKE_MAKE_PROGRAM={make_program}"],
                     [cmake, "--build", str(build)]):
            run = subprocess.run(step, capture_output=True, text=True)
            if run.returncode != 0:
                sys.exit(f"check_ceres_objects self-test: {' '.join(step)} failed:\n{run.stdout}{run.stderr}")
        fake = str(src / "fake_ceres_root" / "include")
        problems, n, stale = check(build, generator, make_program, [fake])
        text = "\n".join(problems)
        if stale:
            failures.append(f"objects just built were called out of date: {stale}")
        # A source edited after its object was built: that object's record is stale (skipped, named
        # as such), while the planted object is still caught.
        future = time.time() + 3600
        os.utime(src / "clean.cpp", (future, future))
        again, _, stale_after = check(build, generator, make_program, [fake])
        if not any("clean.cpp" in o for o in stale_after) or len(again) != 2:
            failures.append(f"a stale object was not set apart (stale {stale_after}, problems {again})")
        if n < 4:
            failures.append(f"read {n} objects, expected 4")
        if not re.search(r"planted_header\.cpp\.o \(target planted_header\) was compiled with \d+ Ceres header", text):
            failures.append("the object that includes <ceres/version.h> was not named")
        if "target planted_path has Ceres' include folder" not in text:
            failures.append("the Ceres include folder on planted_path's include path was not named")
        for passing in ("target clean_target", "target epuck2_fit"):
            if passing in text:
                failures.append(f"{passing} was named wrongly")
        if len(problems) != 2:
            failures.append(f"expected 2 problems, found {len(problems)}")
        if failures:
            sys.exit(f"check_ceres_objects self-test ({generator}) failed:\n  " + "\n  ".join(failures + problems))
        print(f"check_ceres_objects self-test ({generator}): empty build tree refused; of {n} objects, the planted "
              f"Ceres header and the planted include folder caught, the clean target and epuck2_fit passed")


def main():
    args = sys.argv[1:]
    if args and args[0] == "--self-test":
        if len(args) != 5:
            sys.exit(__doc__)
        self_test(*args[1:])
        return
    if len(args) < 3 or (len(args) - 3) % 2:
        sys.exit(__doc__)
    build, generator, make_program = pathlib.Path(args[0]), args[1], args[2]
    ceres_includes = [args[i + 1] for i in range(3, len(args), 2) if args[i] == "--ceres-include"]
    problems, n, stale = check(build, generator, make_program, ceres_includes)
    if problems:
        sys.exit("Ceres outside lib/fit (state the fit through epuck2/fit/problem.hpp, fit_curve, fit::Jet):\n  " +
                 "\n  ".join(problems))
    print(f"no object outside lib/fit was compiled with a Ceres header ({n} objects' dependencies read), "
          "and no other target has Ceres' include folder on its include path" +
          (f"; {len(stale)} older objects not checked (older than their own sources: targets this build does not "
           f"make, e.g. {stale[0]})" if stale else ""))


main()
