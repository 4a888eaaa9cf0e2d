#!/usr/bin/env python3
"""Fails when a source file outside lib/fit includes a Ceres header or names `ceres::`, or a CMake
file outside lib/fit links a Ceres target: the fitting engine (lib/fit) is the one user of Ceres,
and every other part of the project (apps, the other libraries, the ARGoS plug-in, validation,
bench, fuzz, examples, tests) states its fits through lib/fit's API (epuck2/fit/problem.hpp,
fit_curve, fit_robust) and its autodiff scalar epuck2::fit::Jet. No test is exempt: the tests of
lib/fit itself go through the same API.

usage: check_ceres_in_lib_fit.py SOURCE_DIR
       check_ceres_in_lib_fit.py --self-test   (plants each kind of use and checks it is caught)
"""
import pathlib
import re
import sys

SOURCE_SUFFIXES = {".cpp", ".hpp", ".h", ".cc", ".cxx", ".hh", ".inl", ".ipp"}
# A Ceres header included (<ceres/...> or "ceres/..."), or the namespace named (code or comment:
# a comment that names ceres:: is a use another engineer copies).
SOURCE_USE = re.compile(r'#\s*include\s*[<"]ceres/|\bceres::')
CMAKE_USE = re.compile(r'\bCeres::')
SKIP_DIRS = {".git"}


def uses(path: pathlib.Path, text: str):
    pattern = CMAKE_USE if path.name == "CMakeLists.txt" or path.suffix == ".cmake" else SOURCE_USE
    return [(n, line.strip()) for n, line in enumerate(text.splitlines(), 1) if pattern.search(line)]


def checked(root: pathlib.Path):
    for path in sorted(root.rglob("*")):
        rel = path.relative_to(root)
        if not path.is_file():
            continue
        if rel.parts[:2] == ("lib", "fit") or any(p in SKIP_DIRS or p.startswith("build") for p in rel.parts):
            continue
        if path.suffix in SOURCE_SUFFIXES or path.name == "CMakeLists.txt" or path.suffix == ".cmake":
            yield path, rel


def scan(root: pathlib.Path):
    """Every use outside lib/fit under root, and how many files were checked."""
    bad, count = [], 0
    for path, rel in checked(root):
        count += 1
        for n, line in uses(path, path.read_text(errors="replace")):
            bad.append(f"  {rel}:{n}: {line}")
    return bad, count


def self_test():
    import tempfile
    planted = {
        "apps/a.cpp": "#include <ceres/ceres.h>\n",
        "lib/diagnose/src/b.hpp": '#include "ceres/jet.h"\n',
        "validation/nist/c.cpp": "  ceres::Problem problem;\n",
        "tests/d.cpp": "// the same code with ceres::Jet\n",
        "lib/virtual_robot/CMakeLists.txt": "target_link_libraries(x PRIVATE Ceres::ceres)\n",
    }
    allowed = {
        "lib/fit/src/e.cpp": "#include <ceres/ceres.h>\nceres::Solve(o, &p, &s);\n",
        "lib/fit/CMakeLists.txt": "target_link_libraries(epuck2_fit PRIVATE Ceres::ceres)\n",
        "apps/f.cpp": "// Ceres' Jet, epuck2::fit::Jet<4>; a class named ceresish\n",
        "build-x/g.cpp": "ceres::Solve(o, &p, &s);\n",
    }
    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp)
        for name, text in {**planted, **allowed}.items():
            (root / name).parent.mkdir(parents=True, exist_ok=True)
            (root / name).write_text(text)
        bad, _ = scan(root)
    caught = {line.split(":")[0].strip() for line in bad}
    failures = [f"not caught: {name}" for name in planted if name not in caught]
    failures += [f"caught wrongly: {name}" for name in allowed if name in caught]
    if failures or len(bad) != len(planted):
        sys.exit("check_ceres_in_lib_fit self-test failed:\n  " + "\n  ".join(failures + bad))
    print(f"check_ceres_in_lib_fit self-test: {len(planted)} planted uses caught, {len(allowed)} allowed files passed")


def main():
    if len(sys.argv) == 2 and sys.argv[1] == "--self-test":
        self_test()
        return
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    root = pathlib.Path(sys.argv[1])
    if not (root / "lib" / "fit").is_dir():
        sys.exit(f"check_ceres_in_lib_fit: {root} holds no lib/fit: not the project's source directory")
    bad, count = scan(root)
    if bad:
        sys.exit("Ceres used outside lib/fit (state the fit through epuck2/fit/problem.hpp, fit::Jet):\n" + "\n".join(bad))
    print(f"no file outside lib/fit uses Ceres ({count} source and CMake files checked)")


main()
