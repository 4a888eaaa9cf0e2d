#!/usr/bin/env python3
"""Fails when a source file of apps/ chooses what to do by the log kind: a `case` label of a
logs::Kind, a comparison with a logs::Kind enumerator, a comparison with a kind's name as a string
literal ("battery"), or a switch on a model variant's index(). The CLI parses options and chooses
outputs; what differs between kinds is lib/models' kind facts (kind_facts.hpp), the model types'
overloads (lib/models simulate_log.hpp, lib/coefficients codegen.hpp) and the one dispatch from a
kind's name to its model type (lib/coefficients model_file.hpp: AnyModel, model_from_json).

Comments are left out before matching; string literals are kept (a kind's name is one). Not
flagged: naming a kind without comparing it (a list of the subcommands' kinds, an assignment),
and reading a battery-only option into the battery's model type (std::get<BatteryModel>), which
is the option's own type, not a choice between kinds.

usage: check_kind_switches.py SOURCE_DIR     (checks SOURCE_DIR/apps)
       check_kind_switches.py --self-test    (plants each form and checks it is caught)
"""
import pathlib
import re
import sys

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
    for b in bad:
        print("self-test: wrongly judged:", b)
    if bad:
        sys.exit(1)
    print(f"check_kind_switches self-test: {len(caught)} planted switches caught, {len(passed)} other uses passed")


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    root = pathlib.Path(sys.argv[1])
    rules = patterns(kinds_of(root))
    bad = []
    files = sorted(p for p in (root / "apps").rglob("*") if p.suffix in {".cpp", ".hpp", ".h"})
    for path in files:
        for n, what, line in findings(path.read_text(errors="replace"), rules):
            bad.append(f"{path.relative_to(root)}:{n}: {what}: {line}")
    if bad:
        print("\n".join(bad))
        print(f"{len(bad)} per-kind choices in apps/: read the kind's facts (lib/models kind_facts.hpp) or visit its "
              "model (lib/coefficients AnyModel) instead")
        sys.exit(1)
    print(f"check_kind_switches: {len(files)} files of apps/, no per-kind switch")


main()
