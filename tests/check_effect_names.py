#!/usr/bin/env python3
"""Fails when an effect's catalogue name appears as a string literal in a source file outside its
one definition, lib/models/include/epuck2/models/effects.hpp (tests, docs and data aside): the
diagnosis, the coefficient files, codegen, simulate, the reports and the ARGoS plug-in iterate over
the registry instead of naming effects.

usage: check_effect_names.py SOURCE_DIR
"""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1])
registry = root / "lib/models/include/epuck2/models/effects.hpp"
names = re.findall(r'\{"([a-z0-9_]+)", "[^"]*",\s*(?:\n\s*)?Home::', registry.read_text())
if len(names) < 10:
    sys.exit(f"check_effect_names: found only {len(names)} effects in {registry}: the pattern no longer matches the registry")
literal = re.compile(r'"(' + "|".join(map(re.escape, sorted(set(names)))) + r')"')
skip_parts = {"tests", "docs", "data", "build", ".git", "fuzz"}
suffixes = {".cpp", ".hpp", ".h", ".cc", ".py", ".sh"}
# Independent checkers that must not use the code they check (they recompute from the JSON by the
# documented formulas): they may name a file's keys.
independent = {pathlib.Path("examples/check_plugin_models.py")}
bad = []
for path in sorted(root.rglob("*")):
    rel = path.relative_to(root)
    if not path.is_file() or path.suffix not in suffixes or path == registry:
        continue
    if rel in independent or any(p in skip_parts or p.startswith("build") for p in rel.parts):
        continue
    for n, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
        for m in literal.finditer(line):
            bad.append(f"{rel}:{n}: the effect name {m.group(0)} (take it from lib/models' registry, effects.hpp)")
if bad:
    print("\n".join(bad))
    print(f"{len(bad)} effect names written outside the registry")
    sys.exit(1)
print(f"check_effect_names: {len(set(names))} effects, named only in {registry.relative_to(root)}")
