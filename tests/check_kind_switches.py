#!/usr/bin/env python3
"""Fails when a source file of apps/ or lib/ chooses what to do by the log kind: a `case` label of a
logs::Kind, a comparison with a logs::Kind enumerator, a comparison with a kind's name as a string
literal ("battery"), or a switch on a model variant's index(). The CLI parses options and chooses
outputs; what differs between kinds is lib/models' kind facts (kind_facts.hpp), the model types'
overloads (lib/models simulate_log.hpp, lib/coefficients codegen.hpp) and the one dispatch from a
kind's name to its model type (lib/coefficients model_file.hpp: AnyModel, model_from_json).

In lib/ a per-kind fact (a column's range, a label, a rail, a sensor count) is read from
kind_facts.hpp, and each job has one dispatch from a kind to that kind's own code, a table keyed
by the kind where it can be (lib/diagnose kind_table.hpp, lib/models effects.hpp
kind_catalogues(), lib/logs to_string). The few that remain in the form this check sees are in
LIB_ALLOWED, each with its number of matching lines and why it stays: a file with more (or fewer)
fails, so that a new switch cannot hide in an allowed file and the list stays exact.

Comments are left out before matching; string literals are kept (a kind's name is one). Not
flagged: naming a kind without comparing it (a list of the subcommands' kinds, an assignment),
and reading a battery-only option into the battery's model type (std::get<BatteryModel>), which
is the option's own type, not a choice between kinds.

usage: check_kind_switches.py SOURCE_DIR         (checks SOURCE_DIR/apps)
       check_kind_switches.py SOURCE_DIR lib     (checks SOURCE_DIR/lib, with LIB_ALLOWED)
       check_kind_switches.py --self-test        (plants each form and checks it is caught)
"""
import pathlib
import re
import sys
import tempfile

# The per-kind choices kept in lib/: file -> (matching lines, why it stays).
LIB_ALLOWED = {
    "lib/virtual_robot/src/reference_logs.cpp": (
        6, "the one dispatch from a kind to its generator of reference logs (a switch: -Wswitch names a new kind)"),
    "lib/calibrate/src/battery_fit.cpp": (
        1, "the battery fit's input check: it refuses a log of another kind (no choice between kinds)"),
    "lib/calibrate/src/charge_map.cpp": (
        1, "the charge map's input filter: it reads battery logs only (no choice between kinds)"),
}

# The kinds: logs::Kind's enumerators (lib/logs log.hpp), read from the source.
ENUM = re.compile(r"enum\s+class\s+Kind\s*(?::\s*\w+\s*)?\{([^}]*)\}")


def kinds_of(root):
    header = root / "lib/logs/include/epuck2/logs/log.hpp"
    m = ENUM.search(header.read_text())
    if not m:
        sys.exit(f"check_kind_switches: no `enum class Kind {{...}}` in {header}: the pattern no longer matches")
    names = [re.sub(r"//.*", "", n).split("=")[0].strip() for n in m.group(1).split(",")]
    names = [n for n in names if n]
    if len(names) < 6:
        sys.exit(f"check_kind_switches: found only {len(names)} kinds in {header}")
    return names


def without_comments(text):
    """The text with // and /* */ comments blanked (newlines kept), string and char literals kept."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(text[i:j + 1])
            i = j + 1
        elif text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * text.count("\n", i, j))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def patterns(kinds):
    k = "|".join(map(re.escape, kinds))
    enumerator = r"(?:\w+::)*Kind::(?:" + k + r")\b"
    literal = r'"(?:' + k + r')"'
    return [
        (re.compile(r"\bcase\s+" + enumerator), "a case label on the kind"),
        (re.compile(r"(?:==|!=)\s*" + enumerator + r"|" + enumerator + r"\s*(?:==|!=)"), "a comparison with a kind"),
        (re.compile(r"(?:==|!=)\s*" + literal + r"|" + literal + r"\s*(?:==|!=)"), "a comparison with a kind's name"),
        (re.compile(r"\bswitch\s*\([^)]*\.index\(\)\s*\)"), "a switch on a variant's index()"),
    ]


def findings(text, rules):
    out = []
    for n, line in enumerate(without_comments(text).splitlines(), 1):
        for rule, what in rules:
            if rule.search(line):
                out.append((n, what, line.strip()))
    return out


def sources(folder):
    return sorted(p for p in folder.rglob("*") if p.suffix in {".cpp", ".hpp", ".h"})


def check_tree(root, rules, folder, allowed):
    """The lines of per-kind choices in root/folder that `allowed` does not cover, and the files checked."""
    files = sources(root / folder)
    bad = []
    for path in files:
        rel = path.relative_to(root).as_posix()
        found = [f"{rel}:{n}: {what}: {line}" for n, what, line in findings(path.read_text(errors="replace"), rules)]
        if rel in allowed:
            count, why = allowed[rel]
            if len(found) != count:
                bad.append(f"{rel}: {len(found)} per-kind choices, the allow-list says {count} ({why})")
                bad.extend(found)
        else:
            bad.extend(found)
    for rel in allowed:
        if not (root / rel).is_file():
            bad.append(f"{rel}: in the allow-list but no longer a file")
    return bad, files


def self_test_lib(rules):
    """Plants in a lib/ tree: a switch in a file not allowed, one more in an allowed file, a stale entry."""
    allowed = {"lib/a/kept.cpp": (1, "test: one dispatch kept")}
    kept = "int f(Kind k) {\n  switch (k) {\n    case Kind::drive: return 1;\n  }\n}\n"
    trees = {
        "clean": ({"lib/a/kept.cpp": kept, "lib/b/other.cpp": "int g() { return 0; }\n"}, False),
        "a switch in another file": ({"lib/a/kept.cpp": kept, "lib/b/other.cpp": 'bool g(const std::string& kind) { return kind == "camera"; }\n'}, True),
        "one more in the allowed file": ({"lib/a/kept.cpp": kept + "bool h(Kind k) { return k == logs::Kind::light; }\n"}, True),
        "the allowed file gone": ({"lib/b/other.cpp": "int g() { return 0; }\n"}, True),
    }
    wrong = []
    for name, (files, must_fail) in trees.items():
        with tempfile.TemporaryDirectory() as d:
            root = pathlib.Path(d)
            for rel, text in files.items():
                (root / rel).parent.mkdir(parents=True, exist_ok=True)
                (root / rel).write_text(text)
            bad, _ = check_tree(root, rules, "lib", allowed)
            if bool(bad) != must_fail:
                wrong.append(f"lib tree '{name}': {'passed' if not bad else 'failed'} ({bad})")
    return wrong, len(trees)


def self_test():
    kinds = ["battery", "proximity", "light", "ground", "camera", "drive"]
    rules = patterns(kinds)
    caught = [
        "switch (log.kind) {\n  case logs::Kind::proximity: break;\n}",
        "  case Kind::drive: return 1;",
        "if (logs_kind != logs::Kind::battery && x) {}",
        "if (epuck2::logs::Kind::camera == k) {}",
        'if (kind == "proximity") f();',
        'else if ("light" != name) g();',
        "switch (m.index()) {",
    ]
    passed = [
        "for (logs::Kind kind : {logs::Kind::proximity, logs::Kind::light}) {}",
        "like.kind = logs::Kind::battery;",
        '// if (kind == "battery") in a comment',
        '/* case logs::Kind::drive: */ int x = 0;',
        'const char* s = "kind == \\"battery\\" is no code";',
        'return std::get<models::sensors::BatteryModel>(*coefficients_model("battery", source)).tables;',
        'if (o.kind == "all") {}',
    ]
    bad = [c for c in caught if not findings(c, rules)] + [p for p in passed if findings(p, rules)]
    lib_wrong, trees = self_test_lib(rules)
    for b in bad + lib_wrong:
        print("self-test: wrongly judged:", b)
    if bad or lib_wrong:
        sys.exit(1)
    print(f"check_kind_switches self-test: {len(caught)} planted switches caught, {len(passed)} other uses passed, "
          f"{trees} lib/ trees judged right with an allow-list")


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    root = pathlib.Path(sys.argv[1])
    folder = sys.argv[2] if len(sys.argv) > 2 else "apps"
    if folder not in ("apps", "lib"):
        sys.exit(f"check_kind_switches: expected apps or lib, got {folder!r}")
    rules = patterns(kinds_of(root))
    bad, files = check_tree(root, rules, folder, LIB_ALLOWED if folder == "lib" else {})
    if bad:
        print("\n".join(bad))
        print(f"{len(bad)} per-kind choices in {folder}/: read the kind's facts (lib/models kind_facts.hpp) or visit its "
              "model (lib/coefficients AnyModel) instead" +
              ("; a dispatch that must stay goes in LIB_ALLOWED with its reason" if folder == "lib" else ""))
        sys.exit(1)
    kept = sum(n for n, _ in LIB_ALLOWED.values()) if folder == "lib" else 0
    print(f"check_kind_switches: {len(files)} files of {folder}/, no per-kind switch" +
          (f" beyond the {kept} lines of {len(LIB_ALLOWED)} allowed dispatch points" if folder == "lib" else ""))


main()
