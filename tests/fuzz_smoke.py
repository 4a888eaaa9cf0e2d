#!/usr/bin/python3
"""Mutation smoke test of the epuck2-fit command line (CTest: fuzz_smoke).

Runs every subcommand (battery, table5, proximity, light, ground, camera, drive, diagnose,
simulate, codegen, generate, nist) on a few hundred inputs derived from the shipped logs,
coefficient files, diagnosis files and NIST StRD data files (simulate KIND --like with mutated logs
or model files, codegen of diagnosis files, diagnose --coefficients, battery --charge-map, nist on
a mutated .dat file, generate with a bad --seed or an --out-dir that cannot be a folder) by
seeded mutations (byte flips, truncations, duplicated and deleted lines, huge / NaN / inf numbers,
CR-only line ends, NUL and ESC bytes, tiny logs) and on out-of-range numeric options, and checks
the command line's contract. A fixed set of cases runs first whatever the seed (tiny logs and
repeated times of every kind through its fit and diagnose, every numeric option at the edges of its
domain, infinite numbers in the coefficient files codegen reads); then --cases random ones.

  * no signal and no hang: the exit code is 0, 1 or 2;
  * every exit 2 names the bad input: FILE:LINE:COLUMN of the mutated file (a log, a JSON
    file, a .dat file: the line and the column, always), or the option;
  * a coefficient file written (exit 0) holds no NaN, and no null unless its object says why
    (a key containing "reason");
  * on failure (exit 1 or 2) the -o output is untouched: it is created beforehand with known
    bytes and compared afterwards;
  * a header written by `codegen` compiles (c++ -fsyntax-only against lib/models);
  * a log written by `simulate` holds no NaN or infinity;
  * generate writes logs without a NaN or an infinity, and a refused generate creates no folder;
  * every subcommand whose standard output fails (/dev/full) exits 2 saying "standard output",
    `-o -` (the file on standard output) included;
  * a model file with one key of its schema misspelt (a section, a parameter, a noise channel or
    key, an effect) is refused, exit 2 at FILE:LINE:COLUMN, by simulate --like, codegen and
    diagnose --coefficients alike: never dropped in silence.

Usage: fuzz_smoke.py --exe build/bin/epuck2-fit --source . [--cases 300] [--seed 1]
Exit status 0 when every case holds, 1 otherwise; each violation is listed with the command and
the input that triggered it (kept under --keep DIR when given).
"""
import argparse
import json
import math
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time

KINDS = ["battery", "proximity", "light", "ground", "camera", "drive"]
SENSOR_COMMANDS = ["proximity", "light", "ground", "camera", "drive"]
HEAD_LINES = 60          # lines of each shipped log a base input keeps (keeps every run short)
RUN_TIMEOUT_S = 60       # a run slower than this on a 60-line log is reported as a hang
SENTINEL = b"epuck2 fuzz_smoke sentinel: a failed run must leave this file as it is\n"

NON_FINITE_CELL_RE = re.compile(rb"(?im)(?:^|,)\s*[-+]?(?:nan|inf(?:inity)?)\s*(?=,|$)")
NUMBER_RE = re.compile(rb"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")
SPECIAL_NUMBERS = [b"nan", b"NaN", b"inf", b"-inf", b"Infinity", b"1e999", b"-1e999", b"1e308", b"-1e308",
                   b"4.9e-324", b"0x1p3", b"1e", b"--1", b"", b" ", b"1,5", b"99999999999999999999",
                   b"-0", b"0", b"1e-320"]


def read(path):
    with open(path, "rb") as f:
        return f.read()


# ----- mutations ---------------------------------------------------------------------------------

def m_byte_flip(rng, data):
    if not data:
        return data
    b = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        i = rng.randrange(len(b))
        b[i] ^= 1 << rng.randrange(8)
    return bytes(b)


def m_truncate(rng, data):
    return data[:rng.randrange(len(data) + 1)]


def split_lines(data):
    return data.split(b"\n")


def m_duplicate_line(rng, data):
    lines = split_lines(data)
    i = rng.randrange(len(lines))
    lines.insert(i, lines[i])
    return b"\n".join(lines)


def m_delete_line(rng, data):
    lines = split_lines(data)
    if len(lines) > 1:
        del lines[rng.randrange(len(lines))]
    return b"\n".join(lines)


def m_special_number(rng, data):
    spans = [m.span() for m in NUMBER_RE.finditer(data)]
    if not spans:
        return data
    for _ in range(rng.randint(1, 3)):
        a, b = rng.choice(spans)
        data = data[:a] + rng.choice(SPECIAL_NUMBERS) + data[b:]
        spans = [m.span() for m in NUMBER_RE.finditer(data)]
        if not spans:
            break
    return data


def m_scale_number(rng, data):
    """A plausible but wrong number: one value times 10^k or negated."""
    spans = [m.span() for m in NUMBER_RE.finditer(data)]
    if not spans:
        return data
    a, b = rng.choice(spans)
    try:
        v = float(data[a:b])
    except ValueError:
        return data
    v = -v if rng.random() < 0.3 else v * 10.0 ** rng.choice([-300, -5, 3, 12, 300])
    return data[:a] + repr(v).encode() + data[b:]


def m_cr_only(rng, data):
    return data.replace(b"\n", b"\r")


def m_crlf(rng, data):
    return data.replace(b"\n", b"\r\n")


def m_nul(rng, data):
    i = rng.randrange(len(data) + 1)
    return data[:i] + b"\0" + data[i:]


def m_esc(rng, data):
    i = rng.randrange(len(data) + 1)
    return data[:i] + rng.choice([b"\x1b[31m", b"\x1b", b"\x1b]0;x\x07"]) + data[i:]


def m_tiny(rng, data):
    """The header (with any comment lines) and 0, 1 or 2 data rows."""
    lines = split_lines(data)
    header = 0
    while header < len(lines) and lines[header].startswith(b"#"):
        header += 1
    return b"\n".join(lines[:header + 1 + rng.randint(0, 2)]) + b"\n"


def m_swap_columns(rng, data):
    lines = split_lines(data)
    h = 0
    while h < len(lines) and lines[h].startswith(b"#"):
        h += 1
    if h >= len(lines):
        return data
    cols = lines[h].split(b",")
    if len(cols) > 1:
        i, j = rng.sample(range(len(cols)), 2)
        cols[i], cols[j] = cols[j], cols[i]
        lines[h] = b",".join(cols)
    return b"\n".join(lines)


def m_long_line(rng, data):
    lines = split_lines(data)
    i = rng.randrange(len(lines))
    lines[i] = lines[i] + b"," + b"9" * rng.choice([100, 5000, 100000])
    return b"\n".join(lines)


def m_bom(rng, data):
    return b"\xef\xbb\xbf" + data


MUTATIONS = [m_byte_flip, m_truncate, m_duplicate_line, m_delete_line, m_special_number, m_special_number,
             m_scale_number, m_cr_only, m_crlf, m_nul, m_esc, m_tiny, m_swap_columns, m_long_line, m_bom]


def mutate(rng, data):
    names = []
    for _ in range(rng.choice([1, 1, 1, 2])):
        m = rng.choice(MUTATIONS)
        data = m(rng, data)
        names.append(m.__name__[2:])
    return data, "+".join(names)


# ----- checks ------------------------------------------------------------------------------------

def misspell(rng, key, taken):
    """A plausible typo of `key` (two neighbours swapped, a letter dropped, doubled or changed)
    that is neither the key nor another key beside it."""
    for _ in range(50):
        i = rng.randrange(len(key))
        how = rng.randrange(4)
        if how == 0 and len(key) > 1:
            i = min(i, len(key) - 2)
            typo = key[:i] + key[i + 1] + key[i] + key[i + 2:]
        elif how == 1 and len(key) > 1:
            typo = key[:i] + key[i + 1:]
        elif how == 2:
            typo = key[:i + 1] + key[i:]
        else:
            typo = key[:i] + rng.choice("aeiourstnxz") + key[i + 1:]
        if typo != key and typo not in taken:
            return typo
    return key + "x"


def nulls_without_reason(node, where="$", excused=False, parent=None, name=None, grandparent=None):
    """Paths of NaN/inf numbers and of nulls that no reason covers. A reason is a key holding
    'reason' or named 'why' in the null's object or above it, a sibling 'NAME_why', or, for a
    standard error (std_errors.NAME, std_errors.NAME[i]), an entry NAME (NAME[i]) of the
    'std_error_why' object beside 'std_errors' (the coefficient files' contract)."""
    bad = []

    def why_beside_std_errors(key):
        holder = parent if name == "std_errors" else None
        return isinstance(holder, dict) and isinstance(holder.get("std_error_why"), dict) and key in holder["std_error_why"]

    if isinstance(node, dict):
        here = excused or any(("reason" in k) or k == "why" for k in node)
        for k, v in node.items():
            if v is None:
                if not (here or (k + "_why") in node or why_beside_std_errors(k)):
                    bad.append(where + "." + k + " is null")
            else:
                # A list of standard errors may carry its reasons beside it (cubic_std_error_why).
                list_why = isinstance(v, list) and ((k + "_why") in node or
                                                    (k.endswith("_std_errors") and (k[:-1] + "_why") in node))
                bad += nulls_without_reason(v, where + "." + k, here or list_why, node, k, parent)
    elif isinstance(node, list):
        for i, v in enumerate(node):
            if v is None:
                in_std_errors = (isinstance(grandparent, dict) and isinstance(parent, dict)
                                 and parent is grandparent.get("std_errors")
                                 and isinstance(grandparent.get("std_error_why"), dict)
                                 and "%s[%d]" % (name, i) in grandparent["std_error_why"])
                if not (excused or in_std_errors):
                    bad.append("%s[%d] is null" % (where, i))
            else:
                bad += nulls_without_reason(v, "%s[%d]" % (where, i), excused, node, name, parent)
    elif isinstance(node, float) and not math.isfinite(node):
        bad.append(where + " is " + repr(node))
    return bad


def parse_json_strict(text):
    def reject(token):
        raise ValueError("non-standard JSON number " + token)
    return json.loads(text, parse_constant=reject)


class Smoke:
    def __init__(self, args):
        self.exe = os.path.abspath(args.exe)
        self.src = os.path.abspath(args.source)
        self.cxx = args.cxx
        self.work = tempfile.mkdtemp(prefix="epuck2_fuzz_smoke_")
        self.keep = args.keep
        self.failures = []
        self.runs = 0
        self.codes = {0: 0, 1: 0, 2: 0}
        self.compiled_headers = 0
        self.pchs = {}  # a header's #include lines -> its precompiled preamble (preamble_pch)

    # Base inputs: the first HEAD_LINES lines of the shipped logs.
    def shipped(self, kind):
        d = os.path.join(self.src, "data", "raw", kind)
        return sorted(os.path.join(d, f) for f in os.listdir(d) if f.endswith(".csv"))

    def head(self, path, lines=HEAD_LINES):
        return b"\n".join(read(path).split(b"\n")[:lines]) + b"\n"

    def write(self, case, name, data):
        d = os.path.join(self.work, "case%04d" % case)
        os.makedirs(d, exist_ok=True)
        p = os.path.join(d, name)
        with open(p, "wb") as f:
            f.write(data)
        return p

    def case_dir(self, case):
        return os.path.join(self.work, ("case%06d" if case >= 100000 else "case%04d") % case)

    def fail(self, case, cmd, why, rc, err, files):
        msg = "case %d: %s\n    command: %s\n    exit %s; stderr: %s" % (
            case, why, " ".join(cmd), rc, err.strip()[-600:].replace("\n", "\n      "))
        if self.keep:
            dest = os.path.join(self.keep, os.path.basename(self.case_dir(case)))
            shutil.copytree(self.case_dir(case), dest, dirs_exist_ok=True)
            msg += "\n    inputs kept in " + dest
        self.failures.append(msg)

    def run(self, case, args, mutated, output=None, option=None, json_output=False, header=False, csv_output=False):
        """Runs epuck2-fit ARGS and checks the contract. `mutated`: the file names (basenames) an
        exit 2 may name; `option`: the option an exit 2 may name instead; `csv_output`: the -o
        output is a simulated log (no NaN or infinity in it)."""
        if output:
            with open(output, "wb") as f:
                f.write(SENTINEL)
        cmd = [self.exe] + args
        self.runs += 1
        try:
            p = subprocess.run(cmd, capture_output=True, timeout=RUN_TIMEOUT_S, cwd=self.work)
        except subprocess.TimeoutExpired:
            self.fail(case, cmd, "hang: no exit within %d s" % RUN_TIMEOUT_S, "timeout", "", mutated)
            return
        rc = p.returncode
        err = p.stderr.decode("utf-8", "replace")
        if rc < 0:
            self.fail(case, cmd, "killed by signal %d" % -rc, rc, err, mutated)
            return
        if rc not in (0, 1, 2):
            self.fail(case, cmd, "exit code %d (allowed: 0, 1, 2)" % rc, rc, err, mutated)
            return
        self.codes[rc] += 1
        if rc == 2:
            names = [re.escape(m) for m in mutated]
            # FILE:LINE:COLUMN, whatever the input (a log, a JSON file, a .dat file): an error
            # that names only the file, an entry or a line cannot be found in a long file.
            where = re.search(r"(?:%s):\d+:\d+: " % "|".join(names), err) if names else None
            opt = option and option in err
            if not where and not opt:
                self.fail(case, cmd, "exit 2 without FILE:LINE:COLUMN of %s%s" % (
                    " or ".join(mutated) or "-", (" or the option " + option) if option else ""), rc, err, mutated)
        if output and rc != 0:
            now = read(output) if os.path.exists(output) else None
            if now != SENTINEL:
                self.fail(case, cmd, "failed run changed its -o output (%s)" % (
                    "deleted" if now is None else "%d bytes now" % len(now)), rc, err, mutated)
        if output and rc == 0:
            body = read(output)
            if body == SENTINEL:
                self.fail(case, cmd, "exit 0 but the -o output was not written", rc, err, mutated)
            elif json_output:
                try:
                    bad = nulls_without_reason(parse_json_strict(body.decode("utf-8")))
                except (ValueError, UnicodeDecodeError) as e:
                    bad = ["not strict JSON: %s" % e]
                if bad:
                    self.fail(case, cmd, "coefficient file written with " + "; ".join(bad[:5]), rc, err, mutated)
            elif header:
                self.compile_header(case, cmd, output)
            elif csv_output:
                bad = NON_FINITE_CELL_RE.search(body)
                if bad:
                    self.fail(case, cmd, "simulated log written with a non-finite value %r" % bad.group(0), rc, err, mutated)
        return rc

    def run_full_stdout(self, case, args):
        """ARGS with standard output on /dev/full: exit 2 and "standard output: ..." on stderr."""
        cmd = [self.exe] + args
        self.runs += 1
        try:
            with open("/dev/full", "wb") as full:
                p = subprocess.run(cmd, stdout=full, stderr=subprocess.PIPE, timeout=RUN_TIMEOUT_S, cwd=self.work)
        except subprocess.TimeoutExpired:
            self.fail(case, cmd, "hang: no exit within %d s" % RUN_TIMEOUT_S, "timeout", "", [])
            return
        err = p.stderr.decode("utf-8", "replace")
        if p.returncode in self.codes:
            self.codes[p.returncode] += 1
        if p.returncode != 2 or "standard output: " not in err:
            self.fail(case, cmd + [">/dev/full"], "standard output lost without exit 2 and 'standard output: REASON'",
                      p.returncode, err, [])

    def compile_header(self, case, cmd, header):
        # The header is meant to be included as epuck2/fitted/coefficients.hpp next to lib/models.
        inc = os.path.join(os.path.dirname(header), "inc")
        os.makedirs(os.path.join(inc, "epuck2", "fitted"), exist_ok=True)
        shutil.copy(header, os.path.join(inc, "epuck2", "fitted", "coefficients.hpp"))
        tu = os.path.join(os.path.dirname(header), "tu.cpp")
        with open(tu, "w") as f:
            f.write('#include "epuck2/fitted/coefficients.hpp"\nint main() { return 0; }\n')
        pch = self.preamble_pch(read(header))
        c = subprocess.run([self.cxx, "-std=c++17", "-fsyntax-only"] + (["-include", pch] if pch else []) +
                           ["-I", inc, "-I", os.path.join(self.src, "lib", "models", "include"), tu],
                           capture_output=True, timeout=120)
        self.compiled_headers += 1
        if c.returncode != 0:
            self.fail(case, cmd, "codegen wrote a header that does not compile", 0,
                      c.stderr.decode("utf-8", "replace"), [])

    def preamble_pch(self, text):
        """A precompiled header of the header's own #include lines, when nothing but comments,
        blank lines and `#pragma once` comes before them: the header then compiles exactly as
        alone (its includes are already parsed, in the same order, with the same flags, and its own
        #include lines find them guarded), in ~0.15 s of CPU instead of ~0.5 s (lib/models' headers
        parsed again for each of the ~19 headers). None (compile without) otherwise, or when the
        compiler cannot build one."""
        includes = []
        for line in text.decode("utf-8", "replace").split("\n"):
            stripped = line.strip()
            if stripped.startswith("#include"):
                includes.append(stripped)
            elif stripped and not stripped.startswith("//") and stripped != "#pragma once":
                break
        if not includes:
            return None
        key = tuple(includes)
        if key not in self.pchs:
            d = os.path.join(self.work, "pch%d" % len(self.pchs))
            os.makedirs(d)
            pre = os.path.join(d, "preamble.hpp")
            with open(pre, "w") as f:
                f.write("\n".join(includes) + "\n")
            c = subprocess.run([self.cxx, "-std=c++17", "-x", "c++-header",
                                "-I", os.path.join(self.src, "lib", "models", "include"), pre, "-o", pre + ".gch"],
                               capture_output=True, timeout=120)
            self.pchs[key] = pre if c.returncode == 0 else None
        return self.pchs[key]

    # ----- the cases ---------------------------------------------------------------------------
    def fixed_cases(self, bases, fitted):
        """The inputs every run tries, whatever the seed: tiny logs of every kind through its fit
        and diagnose, repeated times (dt = 0), and every numeric option at the edges of its domain.
        Numbered from 100000 so that they do not collide with the random cases."""
        case = 100000
        for kind in KINDS:
            lines = self.head(bases[kind][0]).split(b"\n")
            h = 0
            while lines[h].startswith(b"#"):
                h += 1
            tiny = {"rows1": lines[:h + 2], "rows2": lines[:h + 3],
                    "same_time": lines[:h + 2] + [lines[h + 1]] * 3}
            for label, rows in tiny.items():
                name = "%s_%s.csv" % (kind, label)
                out = os.path.join(self.work, "case%06d" % case, "out.json")
                log = self.write6(case, name, b"\n".join(rows) + b"\n")
                cmd = "battery" if kind == "battery" else kind
                self.run(case, [cmd, log, "-o", out], [name], output=out, json_output=True)
                case += 1
                out = os.path.join(self.work, "case%06d" % case, "out.json")
                log = self.write6(case, name, b"\n".join(rows) + b"\n")
                self.run(case, ["diagnose", "--json", out, log], [name], output=out)
                case += 1
        battery_logs = [p for p in bases["battery"] if "robot-a" in p]
        for bad in ["0", "-1", "nan", "inf", "-inf", "1e999", "abc"]:
            out = os.path.join(self.work, "case%06d" % case, "out.csv")
            prof = self.write6(case, "profile.csv", b"time_s,speed_cm_s\n0,7\n60,3\n")
            self.run(case, ["simulate", "battery", "--model", "cubic", "--profile", prof, "--dt", bad, "-o", out], [],
                     output=out, option="--dt")
            case += 1
            out = os.path.join(self.work, "case%06d" % case, "out.json")
            logs = [self.write6(case, os.path.basename(p), self.head(p, 40)) for p in battery_logs]
            self.run(case, ["table5"] + logs + ["--dt", bad, "-o", out], [], output=out, option="--dt")
            case += 1
            out = os.path.join(self.work, "case%06d" % case, "out.json")
            log = self.write6(case, "b.csv", self.head(battery_logs[3]))
            self.run(case, ["battery", log, "--robust", "--robust-scale", bad, "-o", out], [], output=out,
                     option="--robust-scale", json_output=True)
            case += 1
        # Coefficient files with an infinite or huge number where codegen copies it into C++.
        for token in [b"1e999", b"-1e999", b"1e308", b"4.9e-324"]:
            header = os.path.join(self.work, "case%06d" % case, "coefficients.hpp")
            files = []
            for k, path in fitted.items():
                data = read(path)
                if k == "battery":
                    m = NUMBER_RE.search(data, data.find(b'"linear_slope"'))
                    data = data[:m.start()] + token + data[m.end():]
                files.append(self.write6(case, k + ".json", data))
            self.run(case, ["codegen"] + files + ["-o", header], ["battery.json"], output=header, header=True)
            case += 1
        case = self.full_stdout_cases(bases, fitted, case)

    def full_stdout_cases(self, bases, fitted, case):
        """Every subcommand with its standard output on /dev/full (a full disk): exit 2, said."""
        if not os.path.exists("/dev/full"):
            return case
        d = os.path.join(self.work, "case%06d" % case)
        os.makedirs(d, exist_ok=True)
        # Whole logs: a 60-line head of some kinds has no usable fit (exit 1 before printing).
        logs = {k: self.write6(case, k + ".csv", read(bases[k][0])) for k in KINDS}
        battery = [self.write6(case, "t5_" + os.path.basename(p), self.head(p, 40))
                   for p in bases["battery"] if "robot-a" in p]
        profile = self.write6(case, "profile.csv", b"time_s,speed_cm_s\n0,7\n60,3\n")
        commands = [["--help"], ["--version"], ["help", "diagnose"], ["battery", logs["battery"], "--json"], ["table5"] + battery,
                    ["diagnose", "--json", logs["ground"]], ["diagnose", logs["ground"]],
                    ["codegen", fitted["ground"], "-o", "-"], ["ground", logs["ground"], "-o", "-"],
                    ["simulate", "battery", "--model", "cubic", "--profile", profile],
                    ["simulate", "battery", "--like", logs["battery"]],
                    ["nist", os.path.join(self.src, "tests", "data", "nist"), "--json"]]
        commands += [[k, logs[k], "--json"] for k in SENSOR_COMMANDS]
        commands += [["simulate", k, "--like", logs[k], "--coefficients", fitted[k]] for k in SENSOR_COMMANDS]
        for c in commands:
            self.run_full_stdout(case, c)
        return case + 1

    def write6(self, case, name, data):
        d = os.path.join(self.work, "case%06d" % case)
        os.makedirs(d, exist_ok=True)
        p = os.path.join(d, name)
        with open(p, "wb") as f:
            f.write(data)
        return p

    def main(self, cases, seed):
        rng = random.Random(seed)
        bases = {k: self.shipped(k) for k in KINDS}
        fitted = {k: os.path.join(self.src, "data", "fitted", k + ".json") for k in ["battery"] + SENSOR_COMMANDS}
        self.fixed_cases(bases, fitted)
        diagnoses = {k: os.path.join(self.src, "data", "fitted", "reports", "diagnose_%s.json" % k) for k in KINDS}
        kinds_cycle = (["battery", "table5", "diagnose", "simulate", "codegen", "options"] + SENSOR_COMMANDS +
                       ["simulate_like", "codegen_diagnoses", "diagnose_coefficients", "charge_map", "nist", "generate",
                        "misspelt_key"])
        for case in range(cases):
            what = kinds_cycle[case % len(kinds_cycle)]
            out_json = os.path.join(self.work, "case%04d" % case, "out.json")
            if what in SENSOR_COMMANDS or what == "battery":
                src = rng.choice(bases[what])
                data, how = mutate(rng, self.head(src))
                name = "%s_%s.csv" % (what, how)
                log = self.write(case, name, data)
                self.run(case, [what, log, "-o", out_json], [name], output=out_json, json_output=True)
            elif what == "table5":
                # Every speed of one robot, one of them mutated: the tables can be built.
                logs = []
                victim = rng.randrange(16)
                name = "x"
                for i, src in enumerate(p for p in bases["battery"] if "robot-a" in p):
                    data = self.head(src, 40)
                    n = os.path.basename(src)
                    if i == victim:
                        data, how = mutate(rng, data)
                        n = name = "t5_%s_%s" % (how, n)
                    logs.append(self.write(case, n, data))
                self.run(case, ["table5"] + logs + ["-o", out_json], [name], output=out_json, json_output=False)
            elif what == "diagnose":
                kind = rng.choice(KINDS)
                data, how = mutate(rng, self.head(rng.choice(bases[kind])))
                name = "diag_%s_%s.csv" % (kind, how)
                log = self.write(case, name, data)
                args = ["diagnose", "--json", out_json, log]
                if rng.random() < 0.5:
                    args[1:1] = ["--kind", kind]
                self.run(case, args, [name], output=out_json, json_output=False)
            elif what == "simulate":
                out_csv = os.path.join(self.work, "case%04d" % case, "out.csv")
                model = rng.choice(["simple", "linear", "cubic", "approximated"])
                if rng.random() < 0.5:
                    profile = b"time_s,speed_cm_s\n0,7\n30,3\n60,15\n90,0\n"
                    data, how = mutate(rng, profile)
                    name = "profile_%s.csv" % how
                    prof = self.write(case, name, data)
                    self.run(case, ["simulate", "battery", "--model", model, "--profile", prof, "-o", out_csv],
                             [name], output=out_csv)
                else:
                    prof = self.write(case, "profile.csv", b"time_s,speed_cm_s\n0,7\n60,3\n")
                    data, how = mutate(rng, read(fitted["battery"]))
                    name = "battery_%s.json" % how
                    coeff = self.write(case, name, data)
                    self.run(case, ["simulate", "battery", "--model", model, "--coefficients", coeff, "--profile", prof,
                                    "-o", out_csv], [name], output=out_csv)
            elif what == "codegen":
                header = os.path.join(self.work, "case%04d" % case, "coefficients.hpp")
                files, names = [], []
                victim = rng.choice(list(fitted))
                for k, path in fitted.items():
                    data = read(path)
                    n = k + ".json"
                    if k == victim:
                        data, how = mutate(rng, data)
                        n = "%s_%s.json" % (k, how)
                        names.append(n)
                    files.append(self.write(case, n, data))
                self.run(case, ["codegen"] + files + ["-o", header], names, output=header, header=True)
            elif what == "simulate_like":
                self.simulate_like_case(case, rng, bases, fitted, diagnoses)
            elif what == "codegen_diagnoses":
                # codegen of diagnosis files (diagnose -o), one of them mutated.
                header = os.path.join(self.work, "case%04d" % case, "coefficients.hpp")
                files, names = [], []
                victim = rng.choice(KINDS)
                for k in KINDS:
                    data, n = read(diagnoses[k]), "diagnose_%s.json" % k
                    if k == victim:
                        data, how = mutate(rng, data)
                        n = "diagnose_%s_%s.json" % (k, how)
                        names.append(n)
                    files.append(self.write(case, n, data))
                self.run(case, ["codegen"] + files + ["-o", header], names, output=header, header=True)
            elif what == "diagnose_coefficients":
                # diagnose --coefficients with a mutated model file (a calibration or a diagnosis).
                kind = rng.choice(KINDS)
                base = rng.choice([fitted[kind], diagnoses[kind]])
                data, how = mutate(rng, read(base))
                name = "model_%s_%s.json" % (kind, how)
                coeff = self.write(case, name, data)
                log = self.write(case, "%s.csv" % kind, self.head(rng.choice(bases[kind])))
                self.run(case, ["diagnose", "--coefficients", coeff, "--json", out_json, log], [name], output=out_json)
            elif what == "charge_map":
                self.charge_map_case(case, rng, bases, fitted, out_json)
            elif what == "nist":
                self.nist_case(case, rng, out_json)
            elif what == "generate":
                self.generate_case(case, rng)
            elif what == "misspelt_key":
                self.misspelt_key_case(case, rng, bases, fitted, diagnoses)
            else:
                self.option_case(case, rng, bases, out_json)

    def simulate_like_case(self, case, rng, bases, fitted, diagnoses):
        """simulate KIND --like: the log mutated, or the model file (calibration or diagnosis)."""
        kind = rng.choice(KINDS)
        out_csv = os.path.join(self.work, "case%04d" % case, "out.csv")
        log_data, model_data = self.head(rng.choice(bases[kind])), None
        base = rng.choice([fitted[kind], diagnoses[kind], None])
        if base:
            model_data = read(base)
        if model_data is not None and rng.random() < 0.5:
            model_data, how = mutate(rng, model_data)
            name = "model_%s_%s.json" % (kind, how)
            log_name = "%s.csv" % kind
        else:
            log_data, how = mutate(rng, log_data)
            log_name = name = "like_%s_%s.csv" % (kind, how)
        args = ["simulate", kind, "--like", self.write(case, log_name, log_data)]
        if model_data is not None:
            args += ["--coefficients", self.write(case, name if name.endswith(".json") else "model.json", model_data)]
        if rng.random() < 0.3:
            args += ["--noise", "--seed", str(rng.randrange(1000))]
        self.run(case, args + ["-o", out_csv], [name], output=out_csv, csv_output=True)

    def misspelt_key_case(self, case, rng, bases, fitted, diagnoses):
        """A model file (a calibration or a diagnosis) with one key of its schema misspelt: a
        section, a parameter, a noise channel or a key of one, an effect. Whichever reader takes it
        (simulate --like, codegen, diagnose --coefficients) must refuse it, exit 2 at
        FILE:LINE:COLUMN: a misspelt key that is dropped would leave its value out in silence."""
        kind = rng.choice(KINDS)
        doc = json.loads(read(rng.choice([fitted[kind], diagnoses[kind]])).decode("utf-8"))
        places = [((), k) for k in doc]
        for section in ("parameters", "noise", "effects"):
            if isinstance(doc.get(section), dict):
                places += [((section,), k) for k in doc[section]]
        for channel, v in (doc.get("noise") or {}).items():
            if isinstance(v, dict):
                places += [(("noise", channel), k) for k in v]
        path, key = rng.choice(sorted(places))
        holder = doc
        for p in path:
            holder = holder[p]
        typo = misspell(rng, key, set(holder))
        renamed = {(typo if k == key else k): v for k, v in holder.items()}
        holder.clear()
        holder.update(renamed)
        name = "misspelt_%s_%s.json" % (kind, re.sub(r"[^A-Za-z0-9]+", "-", "_".join(path + (typo,))))
        coeff = self.write(case, name, json.dumps(doc, indent=1).encode("utf-8") + b"\n")
        log = self.write(case, "%s.csv" % kind, self.head(rng.choice(bases[kind])))
        how = rng.choice(["simulate", "codegen", "diagnose"])
        case_dir = os.path.join(self.work, "case%04d" % case)
        if how == "simulate":
            out = os.path.join(case_dir, "out.csv")
            args = ["simulate", kind, "--like", log, "--coefficients", coeff, "-o", out]
        elif how == "codegen":
            out = os.path.join(case_dir, "coefficients.hpp")
            args = ["codegen", coeff, "-o", out]
        else:
            out = os.path.join(case_dir, "out.json")
            args = ["diagnose", "--coefficients", coeff, "--json", out, log]
        rc = self.run(case, args, [name], output=out)
        if rc is not None and rc != 2:
            self.fail(case, [self.exe] + args, "the key '%s' misspelt '%s' (at /%s) was not refused" % (
                key, typo, "/".join(path + (typo,))), rc, "", [name])

    def charge_map_case(self, case, rng, bases, fitted, out_json):
        """battery --charge-map: voltage-only logs (the charge column dropped) through the fitted
        battery file's map; the map file or a log mutated."""
        logs, names = [], []
        mutate_map = rng.random() < 0.6
        victim = rng.randrange(3)
        for i, src in enumerate(rng.sample(bases["battery"], 3)):
            lines = self.head(src).split(b"\n")
            h = 0
            while h < len(lines) and lines[h].startswith(b"#"):
                h += 1
            cols = lines[h].split(b",")
            drop = cols.index(b"charge") if b"charge" in cols else None
            if drop is not None:
                lines = lines[:h] + [b",".join(c for j, c in enumerate(l.split(b",")) if j != drop) if l else l
                                     for l in lines[h:]]
            data, n = b"\n".join(lines), "volts_%d_%s" % (i, os.path.basename(src))
            if not mutate_map and i == victim:
                data, how = mutate(rng, data)
                n = "volts_%s_%s" % (how, os.path.basename(src))
                names.append(n)
            logs.append(self.write(case, n, data))
        data, map_name = read(fitted["battery"]), "map.json"
        if mutate_map:
            data, how = mutate(rng, data)
            map_name = "map_%s.json" % how
            names.append(map_name)
        cmap = self.write(case, map_name, data)
        self.run(case, ["battery"] + logs + ["--charge-map", cmap, "-o", out_json], names, output=out_json,
                 json_output=True)

    # Small StRD problems (a few dozen observations each): a run of two takes well under a second.
    NIST_SMALL = ["Misra1a.dat", "Chwirut2.dat", "DanWood.dat", "BoxBOD.dat", "Rat42.dat", "MGH09.dat"]

    def nist_case(self, case, rng, out_json):
        """nist on a folder of two StRD files, one mutated (its name kept: it names the problem)."""
        d = os.path.join(self.case_dir(case), "nist")
        os.makedirs(d, exist_ok=True)
        victim, other = rng.sample(self.NIST_SMALL, 2)
        data, how = mutate(rng, read(os.path.join(self.src, "tests", "data", "nist", victim)))
        with open(os.path.join(d, victim), "wb") as f:
            f.write(data)
        shutil.copy(os.path.join(self.src, "tests", "data", "nist", other), os.path.join(d, other))
        self.run(case, ["nist", d, "-o", out_json], [victim], output=out_json, json_output=True)

    def generate_case(self, case, rng):
        """generate: a bad --seed or an --out-dir that cannot be a folder (exit 2 naming the option,
        no folder created), or a seeded run whose logs must hold no NaN or infinity."""
        d = self.case_dir(case)
        os.makedirs(d, exist_ok=True)
        kind = rng.choice(KINDS)
        choice = rng.randrange(3)
        if choice == 0:
            out = os.path.join(d, "gen")
            bad = rng.choice(["-1", "abc", "1e3", "1.5", "", "99999999999999999999", "nan", " 7"])
            rc = self.run(case, ["generate", kind, "--out-dir", out, "--seed", bad], [], option="--seed")
            if rc is not None and rc != 2:
                self.fail(case, ["generate", kind, "--seed", bad], "a bad --seed was not refused", rc, "", [])
            if os.path.exists(out):
                self.fail(case, ["generate", kind, "--seed", bad], "a refused generate created its folder", 2, "", [])
        elif choice == 1:
            blocker = os.path.join(d, "a_file")
            with open(blocker, "wb") as f:
                f.write(SENTINEL)
            out = rng.choice([blocker, os.path.join(blocker, "sub"), os.path.join(blocker, "sub", "deeper")])
            rc = self.run(case, ["generate", kind, "--out-dir", out], [], option="--out-dir")
            if rc is not None and rc != 2:
                self.fail(case, ["generate", kind, "--out-dir", out], "an --out-dir that cannot be a folder was not refused", rc, "", [])
            if read(blocker) != SENTINEL:
                self.fail(case, ["generate", kind, "--out-dir", out], "a refused generate changed the file in its way", 2, "", [])
        else:
            out = os.path.join(d, "gen")
            cmd = ["generate", kind, "--out-dir", out, "--seed", str(rng.randrange(2 ** 64))]
            self.run(case, cmd, [])
            for name in sorted(os.listdir(out)) if os.path.isdir(out) else []:
                bad = NON_FINITE_CELL_RE.search(read(os.path.join(out, name)))
                if bad:
                    self.fail(case, cmd, "generate wrote %s with a non-finite value %r" % (name, bad.group(0)), 0, "", [])

    def option_case(self, case, rng, bases, out_json):
        """A numeric option out of its domain: exit 2 naming the option, output untouched."""
        bad = rng.choice(["0", "-1", "nan", "inf", "-inf", "1e999", "1e-320", "abc", ""])
        choice = rng.randrange(3)
        if choice == 0:
            prof = self.write(case, "profile.csv", b"time_s,speed_cm_s\n0,7\n60,3\n")
            out_csv = os.path.join(self.work, "case%04d" % case, "out.csv")
            self.run(case, ["simulate", "battery", "--model", "cubic", "--profile", prof, "--dt", bad, "-o", out_csv],
                     [], output=out_csv, option="--dt")
        elif choice == 1:
            logs = [self.write(case, os.path.basename(p), self.head(p, 40)) for p in bases["battery"] if "robot-a" in p]
            self.run(case, ["table5"] + logs + ["--dt", bad, "-o", out_json], [], output=out_json, option="--dt")
        else:
            log = self.write(case, "b.csv", self.head(bases["battery"][3]))
            self.run(case, ["battery", log, "--robust", "--robust-scale", bad, "-o", out_json], [], output=out_json,
                     option="--robust-scale", json_output=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--exe", required=True, help="the epuck2-fit binary")
    ap.add_argument("--source", required=True, help="the source checkout (data/raw, data/fitted, lib/models)")
    ap.add_argument("--cases", type=int, default=300)
    ap.add_argument("--seed", type=int, default=20261123)
    ap.add_argument("--cxx", default=os.environ.get("CXX", "c++"), help="compiler for the codegen headers")
    ap.add_argument("--keep", help="copy the inputs of failing cases into this folder")
    args = ap.parse_args()
    s = Smoke(args)
    start = time.monotonic()
    try:
        s.main(args.cases, args.seed)
    finally:
        shutil.rmtree(s.work, ignore_errors=True)
    took = time.monotonic() - start
    print("fuzz_smoke: %d runs (%d cases, seed %d) in %.1f s: exit 0 x%d, 1 x%d, 2 x%d; %d codegen headers compiled"
          % (s.runs, args.cases, args.seed, took, s.codes[0], s.codes[1], s.codes[2], s.compiled_headers))
    if s.failures:
        print("fuzz_smoke: %d VIOLATIONS of the command line's contract:" % len(s.failures))
        for f in s.failures:
            print("  " + f)
        return 1
    print("fuzz_smoke: every run kept the contract")
    return 0


if __name__ == "__main__":
    sys.exit(main())
