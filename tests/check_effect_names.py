#!/usr/bin/env python3
"""Fails when an effect's catalogue name appears in a string literal of a source file outside its
one definition, lib/models/include/epuck2/models/effects.hpp: the diagnosis, the coefficient files,
codegen, simulate, the reports and the ARGoS plug-in iterate over the registry instead of naming
effects (issue #19).

What counts as naming an effect:
  - the name as a whole word (letters, digits and _ around it do not belong to it) inside any
    string literal: "long_tail", "the long_tail effect", 'long_tail' (Python, shell), R"(long_tail)";
    adjacent literals are joined first ("long_" "tail"), as the compiler and Python join them;
  - in a shell script, the name as a word anywhere outside a comment (a shell word is a string);
  - in an .argos XML file, the name anywhere outside an XML comment (attributes and text).
Comments (C++, Python, shell, XML), Python docstrings and `#include "..."` paths are not strings.

Checked: every .cpp .hpp .h .cc .py .sh .argos file under SOURCE_DIR except the registry, the
top-level tests/ and docs/ (the issue's "tests and docs aside"; a `tests` folder anywhere else is
checked), argos/tests/ (the ARGoS plug-in's tests: their files write coefficient files naming
effects, as tests/ does, and must not take the names from the code they test), build*/ and .git/,
and the exemptions listed in EXEMPT with their reasons.

The registry's entries are read from effects.hpp; the check fails when it reads fewer entries than
the registry holds (an entry reformatted so that the pattern no longer matches it would otherwise
drop out of the check): the number of entries read must equal the number of `Home::` tokens in
the catalogue functions' code, and `--list` prints the entries read (KIND NAME, one a line) so that
a test (EffectRegistry.TheNameGuardReadsEveryEntry, tests/test_coefficients.cpp) compares them
with the C++ registry itself.

usage: check_effect_names.py SOURCE_DIR
       check_effect_names.py --list SOURCE_DIR   (the registry's entries as the checker reads them)
       check_effect_names.py --self-test         (plants each way of naming an effect; each must fail)
"""
import io
import pathlib
import re
import sys
import tokenize

REGISTRY = pathlib.Path("lib/models/include/epuck2/models/effects.hpp")
SUFFIXES = {".cpp", ".hpp", ".h", ".cc", ".py", ".sh", ".argos"}
EXEMPT_DIRS = {("tests",), ("docs",), ("argos", "tests"), (".git",)}
# Independent checkers that must not use the code they check (they recompute from the JSON by the
# documented formulas): they may name a file's keys.
INDEPENDENT = {pathlib.Path("examples/check_plugin_models.py")}
# (file, a piece of the literal): why it may name an effect. ARGoS's help texts (REGISTER_SENSOR,
# REGISTER_ACTUATOR) take their effect names from the registry too. scripts/mutate.sh's mutants
# quote product code verbatim (the text a mutant replaces must occur in the file): a header's path
# (models/saturation.hpp holds the saturation effect's formula) and code that already takes the
# names from the registry (fx::drive::speed_limit, ...).
EXEMPT = {
    ("scripts/mutate.sh", "lib/models/include/epuck2/models/saturation.hpp"),
    ("scripts/mutate.sh", "{fx::drive::speed_limit, fx::drive::accel_limit, fx::drive::"),
    # round 18's mutants: ARGoS code that reads the effects through the registry's names
    ("scripts/mutate.sh", "c.effects.speed_limit.max_cm_s = firmware_cap_cm_s("),
    ("scripts/mutate.sh", "static const Applied a{fx::light::ambient_offset, fx::light::"),
}


# ----- the registry ------------------------------------------------------------------------------

def cpp_pieces(text):
    """(kind, start, end, body) of C and C++ text: kind 'code', 'comment' or 'string' (body: the
    literal's content), 'include' for an #include's path, 'char' for a character literal."""
    out, i, n, code_start = [], 0, len(text), 0

    def flush(upto):
        if upto > code_start:
            out.append(("code", code_start, upto, text[code_start:upto]))

    while i < n:
        c = text[i]
        if text.startswith("//", i) or text.startswith("/*", i):
            flush(i)
            end = text.find("\n", i) if c == "/" and text[i + 1] == "/" else text.find("*/", i + 2)
            end = n if end < 0 else (end if text[i + 1] == "/" else end + 2)
            out.append(("comment", i, end, text[i:end]))
            i = code_start = end
            continue
        if c == "#" and re.match(r"#\s*include\b", text[i:i + 20]):
            flush(i)
            end = text.find("\n", i)
            end = n if end < 0 else end
            out.append(("include", i, end, text[i:end]))
            i = code_start = end
            continue
        raw = re.match(r'(?:u8|[uUL])?R"([^()\\\s]{0,16})\(', text[i:i + 24])
        if raw and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            flush(i)
            close = ")" + raw.group(1) + '"'
            body_start = i + raw.end()
            end = text.find(close, body_start)
            end = n if end < 0 else end
            out.append(("string", i, end + len(close), text[body_start:end]))
            i = code_start = min(n, end + len(close))
            continue
        if c == '"' or (c == "'" and not (i > 0 and text[i - 1].isdigit())):
            flush(i)
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(("string" if c == '"' else "char", i, j + 1, text[i + 1:j]))
            i = code_start = j + 1
            continue
        i += 1
    flush(n)
    return out


def registry_entries(text):
    """[(kind, name)] of every entry of every `KIND_catalogue()` in effects.hpp's text, and the
    number of `Home::` tokens in those functions' code (one per entry)."""
    code = "".join(body if kind == "code" else (f'"{body}"' if kind == "string" else " ")
                   for kind, _, _, body in cpp_pieces(text))
    entries, homes = [], 0
    for m in re.finditer(r"\b(\w+)_catalogue\(\)\s*\{", code):
        depth, j = 1, m.end()
        while depth and j < len(code):
            depth += {"{": 1, "}": -1}.get(code[j], 0)
            j += 1
        body = code[m.end():j]
        homes += len(re.findall(r"\bHome::(?:effects|parameters|base)\b", body))
        literal = r'"(?:[^"\\\n]|\\.)*"'
        for e in re.finditer(r'\{\s*"([a-z0-9_]+)"\s*,\s*(?:' + literal + r"\s*)+,\s*Home::", body):
            entries.append((m.group(1), e.group(1)))
    return entries, homes


# ----- the literals of a file --------------------------------------------------------------------

class Joined(str):
    """A run of adjacent literals joined; `parts`: the literals (each also checked on its own)."""

    def __new__(cls, parts):
        s = super().__new__(cls, "".join(parts))
        s.parts = list(parts)
        return s


def joined(pieces):
    """Each string literal, and each run of adjacent literals (whitespace between them) joined."""
    out, run = [], []
    for kind, _, _, body in pieces:
        if kind == "string":
            out.append(body)
            run.append(body)
            continue
        if kind == "code" and not body.strip() and run:
            continue
        if len(run) > 1:
            out.append(Joined(run))
        run = []
    if len(run) > 1:
        out.append(Joined(run))
    return out


def python_literals(text):
    """Every string literal of Python text (docstrings aside: a string alone as a statement is a
    comment), runs of adjacent literals joined; f-strings' text parts as literals."""
    out, run, statement_start = [], [], True
    try:
        tokens = list(tokenize.generate_tokens(io.StringIO(text).readline))
    except (tokenize.TokenError, SyntaxError, IndentationError):
        return [text]  # not Python the tokenizer reads: every character counts
    skip = {tokenize.NL, tokenize.COMMENT, tokenize.INDENT, tokenize.DEDENT}
    fstring = {getattr(tokenize, "FSTRING_START", -1), getattr(tokenize, "FSTRING_MIDDLE", -2),
               getattr(tokenize, "FSTRING_END", -3)}
    docstring_run = False
    for k, tok in enumerate(tokens):
        if tok.type in (tokenize.STRING,) or tok.type in fstring:
            if not run:
                docstring_run = statement_start
            if tok.type == tokenize.STRING:
                body = re.sub(r"^[A-Za-z]*", "", tok.string)
                q = 3 if body[:3] in ('"""', "'''") else 1
                run.append(body[q:-q])
            elif tok.type == getattr(tokenize, "FSTRING_MIDDLE", -2):
                run.append(tok.string)
            statement_start = False
            continue
        if tok.type in skip:
            continue
        if run:
            alone = docstring_run and tok.type in (tokenize.NEWLINE, tokenize.ENDMARKER)
            if not alone:
                out.extend(run)
                if len(run) > 1:
                    out.append(Joined(run))
            run = []
        statement_start = tok.type in (tokenize.NEWLINE, tokenize.INDENT, tokenize.DEDENT) or (
            tok.type == tokenize.OP and tok.string == ";")
    if run:
        out.extend(run)
    return out


def shell_text(text):
    """Shell text without its comments: every word of a shell script is a string. A `#` starts a
    comment at the start of a word, outside quotes (here-documents read line by line, so that an
    apostrophe in an embedded program's comment does not open a quote)."""
    out = []
    heredoc = None
    quote = None
    for line in text.splitlines():
        if heredoc is not None:
            if line.strip() == heredoc:
                heredoc = None
                continue
            cut = re.search(r"(^|\s)#", line)
            out.append(line[:cut.start()] if cut else line)
            continue
        kept, i = [], 0
        while i < len(line):
            c = line[i]
            if quote:
                if c == "\\" and quote == '"':
                    kept.append(line[i:i + 2])
                    i += 2
                    continue
                if c == quote:
                    quote = None
            elif c in "'\"":
                quote = c
            elif c == "\\":
                kept.append(line[i:i + 2])
                i += 2
                continue
            elif c == "#" and (i == 0 or line[i - 1] in " \t;|&("):
                break
            kept.append(c)
            i += 1
        text_kept = "".join(kept)
        out.append(text_kept)
        m = re.search(r"<<-?\s*['\"]?(\w+)['\"]?", text_kept)
        if m and not quote:
            heredoc = m.group(1)
    return [line for line in out if line.strip()]


def literals(path: pathlib.Path, text: str):
    if path.suffix == ".py":
        return python_literals(text)
    if path.suffix == ".sh":
        return shell_text(text)
    if path.suffix == ".argos":
        bare = re.sub(r"<!--.*?-->", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
        return [line for line in bare.splitlines() if line.strip()]
    return joined(cpp_pieces(text))


def line_of(text, literal):
    """The line of text where `literal` (or its first line) starts; 0 if not found verbatim."""
    if isinstance(literal, Joined):  # its first literal with its quotes, where the run starts
        for q in ('"', "'"):
            at = text.find(q + literal.parts[0] + q)
            if at >= 0:
                return text.count("\n", 0, at) + 1
        literal = literal.parts[0]
    first = literal.split("\n")[0][:60]
    at = text.find(first) if first else -1
    return text.count("\n", 0, at) + 1 if at >= 0 else 0


def checked(root: pathlib.Path):
    for path in sorted(root.rglob("*")):
        rel = path.relative_to(root)
        if not path.is_file() or path.suffix not in SUFFIXES or rel == REGISTRY or rel in INDEPENDENT:
            continue
        if any(rel.parts[:len(d)] == d for d in EXEMPT_DIRS) or rel.parts[0].startswith("build"):
            continue
        yield path, rel


def scan(root: pathlib.Path, names):
    word = re.compile(r"(?<![A-Za-z0-9_])(" + "|".join(map(re.escape, sorted(names, key=len, reverse=True))) +
                      r")(?![A-Za-z0-9_])")
    bad = []
    for path, rel in checked(root):
        text = path.read_text(errors="replace")
        for lit in literals(path, text):
            for m in word.finditer(lit):
                if any(str(rel) == f and piece in lit for (f, piece) in EXEMPT):
                    continue
                if isinstance(lit, Joined) and any(word.search(part) and m.group(1) in part for part in lit.parts):
                    continue  # already reported in the literal that holds it whole
                shown = lit if len(lit) < 70 else lit[:67] + "..."
                bad.append(f"{rel}:{line_of(text, lit) or '?'}: the effect name '{m.group(1)}' in {shown!r} "
                           "(take it from lib/models' registry, effects.hpp)")
                break
    return bad


def read_registry(root: pathlib.Path):
    path = root / REGISTRY
    entries, homes = registry_entries(path.read_text())
    if len(entries) != homes or not entries:
        sys.exit(f"check_effect_names: read {len(entries)} entries in {REGISTRY} but its catalogues hold {homes} "
                 "(one `Home::` each): an entry is written in a form the checker does not read, "
                 "{\"NAME\", \"MEANING\", Home::...}")
    return entries


def check(root: pathlib.Path):
    entries = read_registry(root)
    names = {n for _, n in entries}
    return scan(root, names), entries, names


# ----- self-test ---------------------------------------------------------------------------------

REGISTRY_TEXT = '''namespace x {
inline const Catalogue& proximity_catalogue() {
  static const Catalogue c{
      {"long_tail", "the sensor still responds", Home::effects, {}},
      // {"not_an_entry", "a comment", Home::effects, {}},
      {"saturation", "readings saturate " "below full scale", Home::effects, {}},
  };
  return c;
}
inline const Catalogue& camera_catalogue() {
  static const Catalogue c{
      {"distortion_k3",
       "the lens's sixth-order term", Home::effects, {}},
  };
  return c;
}
}
'''


def self_test():
    import tempfile
    planted = {
        "apps/a.cpp": 'const char* kPlanted = "long_tail";\n',
        "scripts/b.py": "EFFECT = 'long_tail'\n",
        "lib/diagnose/src/c.cpp": 'std::string s = "the long_tail effect";\n',
        "lib/calibrate/src/d.cpp": 'std::string s = "long_" "tail";\n',
        "argos/src/tests/e.cpp": 'auto n = "saturation";\n',
        "lib/logs/tests/f.py": 'x = "distortion_k3"\n',
        "argos/experiments/g.argos": '<epuck2_proximity effects="long_tail" /> <!-- long_tail -->\n',
        "scripts/h.sh": "diagnose --effects long_tail  # the tail\n",
        "apps/i.cpp": 'auto j = R"({"effects":{"saturation":{}}})";\n',
        "bench/j.py": 'print(f"the {x} long_tail")\n',
    }
    allowed = {
        "tests/k.cpp": 'auto n = "long_tail";\n',
        "docs/l.py": "n = 'long_tail'\n",
        "argos/tests/m.sh": 'd["effects"] = {"long_tail": {}}\n',
        "apps/n.cpp": '// the long_tail effect\n#include "epuck2/models/saturation.hpp"\nauto m = e.tail; char c = \'s\';\n'
                      'std::string s = "long_tails and my_saturation";\n',
        "scripts/o.py": '"""A docstring naming long_tail."""\n# long_tail\nx = 1\n',
        "scripts/p.sh": "# diagnose --effects long_tail\necho ok\n",
        "argos/experiments/q.argos": "<!-- the long_tail effect -->\n<a b=\"c\" />\n",
        "build-x/r.cpp": 'auto n = "long_tail";\n',
    }
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp)
        (root / REGISTRY).parent.mkdir(parents=True)
        (root / REGISTRY).write_text(REGISTRY_TEXT)
        entries = read_registry(root)
        if sorted(entries) != [("camera", "distortion_k3"), ("proximity", "long_tail"), ("proximity", "saturation")]:
            failures.append(f"registry read as {entries}: the entries written over two lines or with a meaning in "
                            "two literals must be read, the commented one not")
        for name, text in {**planted, **allowed}.items():
            (root / name).parent.mkdir(parents=True, exist_ok=True)
            (root / name).write_text(text)
        bad = scan(root, {n for _, n in entries})
        caught = {line.split(":")[0] for line in bad}
        failures += [f"not caught: {name}" for name in planted if name not in caught]
        failures += [f"caught wrongly: {name}" for name in allowed if name in caught]
        # Registry drift: an entry the pattern no longer reads (its name not a plain literal) fails.
        (root / REGISTRY).write_text(REGISTRY_TEXT.replace('{"distortion_k3",', '{kK3Name,'))
        import subprocess
        r = subprocess.run([sys.executable, __file__, str(root)], capture_output=True, text=True)
        if r.returncode == 0 or "read 2 entries" not in r.stdout + r.stderr:
            failures.append(f"an entry the checker cannot read passed (rc {r.returncode}): {r.stdout}{r.stderr}")
    if failures:
        sys.exit("check_effect_names self-test failed:\n  " + "\n  ".join(failures + bad))
    print(f"check_effect_names self-test: {len(planted)} planted names caught, {len(allowed)} allowed files passed, "
          "an unreadable registry entry caught")


def main():
    args = sys.argv[1:]
    if args == ["--self-test"]:
        self_test()
        return
    if len(args) == 2 and args[0] == "--list":
        for kind, name in read_registry(pathlib.Path(args[1])):
            print(kind, name)
        return
    if len(args) != 1:
        sys.exit(__doc__)
    bad, entries, names = check(pathlib.Path(args[0]))
    if bad:
        print("\n".join(bad))
        print(f"{len(bad)} effect names written outside the registry")
        sys.exit(1)
    print(f"check_effect_names: {len(names)} effects ({len(entries)} entries), named only in {REGISTRY}")


main()
