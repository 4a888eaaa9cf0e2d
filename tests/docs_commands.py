#!/usr/bin/env python3
"""The docs run as written (CTest `docs_commands`, issue #24).

Every command block of README.md and docs/*.md is run from the repository root, in a scratch copy
of the repository (so nothing in the tree changes), with the build's `build/bin` on PATH as the
README's set-up says (`export PATH=$PWD/build/bin:$PATH`):

* a block fenced as ```sh or ```bash is a list of commands: it is run with `bash -e -o pipefail`
  and must exit 0;
* a block fenced as ```text whose first line starts with `$ ` is a command and what it printed:
  the command is run and its standard output must be the block's other lines, exactly. A stale
  number in a quoted output fails the suite.

A block that cannot run here (it installs packages, builds ARGoS, needs the user's own logs or
files) carries, on the line right before its fence, the visible marker

    *Not run by the docs test: REASON.*

and is skipped with that reason (printed). A block that runs a part this build left out (the ARGoS
plug-in, or the benchmark programs: the sanitizer build has neither) is skipped, saying so; a build
that has them runs it.

Numbers quoted in prose (or in a block that is no command, like a JSON excerpt) carry, on the line
right before their paragraph or block, an HTML comment (invisible once rendered) naming the command
they come from and the strings quoted:

    <!-- checked against: epuck2-fit proximity data/raw/proximity/*.csv quoting: "197.1 ± 1.3" "1.01104 ± 0.00074" -->

The command is run as above; each string must appear both in what it prints and in the paragraph
(or block) under the comment. A stale number fails the suite; --update does not rewrite these
(say the new number in the prose and in the comment). Synopses of a command's options (`[--json] [-o FILE]`)
are no commands: they are fenced as ```text without `$ `, and are not run.

Usage: docs_commands.py --source DIR --bin DIR [--only FILE] [--list]
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

SKIP = re.compile(r"^\*Not run by the docs test: (.+?)\.?\*\s*$")
CHECKED = re.compile(r"^<!-- checked against: (.+?) quoting: (.+) -->\s*$")
QUOTED = re.compile(r'"((?:[^"\\]|\\.)*)"')


def checked_numbers(path):
    """(line, command, [strings], the text quoted) of every `checked against` comment of a file."""
    out = []
    lines = open(path, encoding="utf-8").read().split("\n")
    for i, line in enumerate(lines):
        m = CHECKED.match(line)
        if not m:
            continue
        strings = [q.replace('\\"', '"') for q in QUOTED.findall(m.group(2))]
        j = i + 1
        if j < len(lines) and lines[j].startswith("```"):  # a block: to its closing fence
            j += 1
            while j < len(lines) and not lines[j].startswith("```"):
                j += 1
        else:  # a paragraph: to the next blank line
            while j < len(lines) and lines[j].strip():
                j += 1
        out.append((i + 1, m.group(1), strings, "\n".join(lines[i + 1:j + 1])))
    return out
FENCE = re.compile(r"^```(\w*)\s*$")


def blocks(path):
    """(line, language, text, skip reason or None) of every fenced block of a Markdown file."""
    out = []
    lines = open(path, encoding="utf-8").read().split("\n")
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m or not m.group(1):
            i += 1
            continue
        lang, start = m.group(1), i
        j = i + 1
        while j < len(lines) and not lines[j].startswith("```"):
            j += 1
        before = next((lines[k] for k in range(start - 1, -1, -1) if lines[k].strip()), "")
        skip = SKIP.match(before)
        out.append((start + 1, lang, "\n".join(lines[start + 1 : j]), skip.group(1) if skip else None))
        i = j + 1
    return out


def copy_tree(src, bin_dir, root):
    """The repository's tracked and untracked-but-not-ignored files copied into ROOT, with the
    build's bin folder (and its lib folder, for scripts/argos-record.sh) linked as build/bin and
    build/lib, as the README's set-up leaves them. Returns the manifest restore_tree puts back:
    every file and link with its lstat (type, mode, size, modification time), every folder."""
    tracked = subprocess.run(["git", "-C", src, "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                             capture_output=True, check=True).stdout.decode().split("\0")
    for f in tracked:
        if not f or not os.path.isfile(os.path.join(src, f)):
            continue
        os.makedirs(os.path.join(root, os.path.dirname(f)), exist_ok=True)
        shutil.copy2(os.path.join(src, f), os.path.join(root, f))
    os.makedirs(os.path.join(root, "build"), exist_ok=True)
    os.symlink(os.path.abspath(bin_dir), os.path.join(root, "build", "bin"))
    # The build's plug-ins (build/lib/argos3, for scripts/argos-record.sh) beside its bin.
    lib = os.path.join(os.path.dirname(os.path.abspath(bin_dir)), "lib")
    if os.path.isdir(lib):
        os.symlink(lib, os.path.join(root, "build", "lib"))
    files, dirs = {}, set()
    for d, subdirs, names in os.walk(root):
        rel = os.path.relpath(d, root)
        dirs.add(rel)
        for n in names + [x for x in subdirs if os.path.islink(os.path.join(d, x))]:
            files[os.path.normpath(os.path.join(rel, n))] = stat_key(os.path.join(d, n))
    return {"files": files, "dirs": dirs}


def stat_key(path):
    st = os.lstat(path)
    return (st.st_mode, st.st_size, st.st_mtime_ns)


def restore_tree(src, bin_dir, root, manifest):
    """ROOT as copy_tree left it: files and folders a block added removed, files it changed
    (type, mode, size or modification time) or removed copied again from SRC, links made again."""
    files, dirs = manifest["files"], manifest["dirs"]
    for d, subdirs, names in os.walk(root, topdown=True):
        rel = os.path.relpath(d, root)
        for x in list(subdirs):
            path, key = os.path.join(d, x), os.path.normpath(os.path.join(rel, x))
            if os.path.islink(path):
                names.append(x)
                subdirs.remove(x)
            elif key not in dirs:
                shutil.rmtree(path)
                subdirs.remove(x)
        for n in names:
            if os.path.normpath(os.path.join(rel, n)) not in files:
                os.remove(os.path.join(d, n))
    for rel, key in files.items():
        path = os.path.join(root, rel)
        try:
            if stat_key(path) == key:
                continue
        except FileNotFoundError:
            pass
        if os.path.isdir(path) and not os.path.islink(path):
            shutil.rmtree(path)
        elif os.path.lexists(path):
            os.remove(path)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        if rel in ("build/bin", "build/lib"):
            os.symlink(os.path.abspath(bin_dir) if rel == "build/bin" else
                       os.path.join(os.path.dirname(os.path.abspath(bin_dir)), "lib"), path)
        else:
            shutil.copy2(os.path.join(src, rel), path)
            os.chmod(path, key[0] & 0o7777)
        files[rel] = stat_key(path)
    for rel in dirs:  # a folder a block removed (its files came back above)
        os.makedirs(os.path.join(root, rel), exist_ok=True)


def parts_not_built(src, bin_dir):
    """{part: (pattern of a block that needs it, reason)} for the optional parts this build lacks:
    the ARGoS plug-in (EPUCK2_BUILD_ARGOS=OFF, or ARGoS not found: scripts/setup-and-test.sh
    --sanitize leaves it out, since an instrumented plug-in cannot load into argos3) and the
    benchmark programs (EPUCK2_BUILD_BENCH=OFF). A build that has them runs every such block."""
    out = {}
    lib = os.path.join(os.path.dirname(os.path.abspath(bin_dir)), "lib", "argos3")
    if not os.path.isfile(os.path.join(lib, "libepuck2_argos_protocols.so")):
        out["argos"] = (re.compile(r"\bargos3\b|argos-record\.sh"),
                        "the ARGoS plug-in is not built in this build (" + lib + " has no libepuck2_argos_protocols.so)")
    with open(os.path.join(src, "bench", "CMakeLists.txt")) as f:
        programs = re.findall(r"add_executable\((\w+)", f.read())
    missing = [p for p in programs if not os.path.isfile(os.path.join(bin_dir, p))]
    if missing:
        out["bench"] = (re.compile(r"\b(" + "|".join(map(re.escape, missing)) + r")\b"),
                        "the benchmark programs are not built in this build (EPUCK2_BUILD_BENCH=OFF)")
    return out


def needs_unbuilt(text, unbuilt):
    """The reason to skip a block that runs a part this build lacks, else None."""
    for pattern, reason in unbuilt.values():
        if pattern.search(text):
            return reason
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source", required=True)
    ap.add_argument("--bin", required=True, help="the build's bin folder (epuck2-fit)")
    ap.add_argument("--only", help="one Markdown file (relative to the source)")
    ap.add_argument("--list", action="store_true", help="list the blocks and what would be done")
    ap.add_argument("--update", action="store_true",
                    help="rewrite every quoted output ($ COMMAND blocks) with what the command prints now "
                         "(the docs' numbers regenerated, as scripts/regenerate.sh does for data/fitted)")
    a = ap.parse_args()
    src = os.path.abspath(a.source)
    files = [a.only] if a.only else ["README.md"] + sorted(
        os.path.join("docs", f) for f in os.listdir(os.path.join(src, "docs")) if f.endswith(".md"))

    unbuilt = parts_not_built(src, a.bin)

    work = tempfile.mkdtemp(prefix="epuck2-docs-")
    root = os.path.join(work, "repo")  # the repository's copy the blocks run in
    manifest = None  # its files as copied (made at the first block run)
    outputs = {}  # a quoted command -> what it printed and its exit code
    failures, ran, skipped = [], 0, 0
    shift = {}  # --update: how far each file's later blocks moved
    try:
        for md in files:
            jobs = [(line, lang, text, skip, None) for line, lang, text, skip in blocks(os.path.join(src, md))]
            jobs += [(line, "checked", command, None, (strings, quoted))
                     for line, command, strings, quoted in checked_numbers(os.path.join(src, md))]
            for line, lang, text, skip, numbers in jobs:
                where = f"{md}:{line}"
                is_output = lang == "text" and text.startswith("$ ")
                if lang not in ("sh", "bash", "checked") and not is_output:
                    continue
                if not skip:
                    skip = needs_unbuilt(text, unbuilt)
                if skip:
                    skipped += 1
                    print(f"skipped {where}: {skip}")
                    continue
                if a.list:
                    print(f"would run {where} ({'numbers in prose' if numbers else 'output' if is_output else 'commands'})")
                    continue
                # The repository as the docs describe it for every block, whatever the blocks before
                # it wrote: copied once, then put back after each block (restore_tree: what a block
                # added is removed, what it changed or removed copied again from the source); 445
                # files copied again for every block cost 0.3-0.7 s each, of which this keeps ~0.02.
                if manifest is None:
                    shutil.rmtree(root, ignore_errors=True)
                    manifest = copy_tree(src, a.bin, root)
                env = dict(os.environ)
                env["PATH"] = os.path.join(root, "build", "bin") + os.pathsep + env.get("PATH", "")
                if is_output:
                    command, expected = text.split("\n", 1)[0][2:], text.split("\n", 1)[1] if "\n" in text else ""
                    script = command
                else:
                    script, expected = text, None
                t0 = time.monotonic()
                # A command whose output is quoted (numbers in prose, a `$ ` block) and that another
                # quote already ran is not run again: it ran on the same tree (put back after each
                # block), in the same folder, with the same binaries, and the commands are seeded
                # (the battery's diagnosis, 2-3 s, is quoted twice). Command blocks always run.
                cached = (numbers is not None or is_output) and script in outputs
                if cached:
                    r = outputs[script]
                else:
                    r = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", script], cwd=root, env=env,
                                       capture_output=True, text=True, timeout=900)
                    if numbers is not None or is_output:
                        outputs[script] = r
                took = time.monotonic() - t0
                ran += 1
                if numbers and r.returncode == 0:
                    strings, quoted = numbers
                    for q in strings:
                        if q not in quoted:
                            failures.append(f"{where}: '{q}' is in the checked-against comment but not in the text under it")
                        elif q not in r.stdout:
                            failures.append(f"{where}: the docs quote '{q}', which `{script}` no longer prints "
                                            f"(a stale number: update the prose and the comment)")
                if r.returncode != 0:
                    failures.append(f"{where}: exit {r.returncode}\n--- the block\n{script}\n--- stderr\n{r.stderr[-3000:]}")
                elif expected is not None and r.stdout.rstrip("\n") != expected.rstrip("\n") and a.update:
                    path = os.path.join(src, md)
                    doc = open(path, encoding="utf-8").read().split("\n")
                    old = text.split("\n")
                    # The block's lines start after its fence (line numbers are 1-based, of the fence).
                    at = line + shift.get(md, 0)  # earlier updates of this file moved its later blocks
                    assert doc[at:at + len(old)] == old, f"{where}: the block moved while updating"
                    new = [old[0]] + r.stdout.rstrip("\n").split("\n")
                    doc[at:at + len(old)] = new
                    shift[md] = shift.get(md, 0) + len(new) - len(old)
                    open(path, "w", encoding="utf-8").write("\n".join(doc))
                    manifest = None  # the next block starts from a new copy, with the updated docs
                    outputs.clear()
                    print(f"updated {where}: the quoted output of `{command}`")
                elif expected is not None and r.stdout.rstrip("\n") != expected.rstrip("\n"):
                    got, want = r.stdout.rstrip("\n").split("\n"), expected.rstrip("\n").split("\n")
                    diff = [f"  line {k + 1}:\n    docs: {w}\n    now:  {g}" for k, (w, g) in
                            enumerate(zip(want + [""] * len(got), got + [""] * len(want))) if w != g][:8]
                    failures.append(f"{where}: the quoted output differs from what `{command}` prints now "
                                    f"(update the docs):\n" + "\n".join(diff))
                print(f"ran {where} in {took:.1f} s{' (its output from an earlier quote of the same command)' if cached else ''}: "
                      f"{'ok' if r.returncode == 0 else 'FAILED'}")
                if manifest is not None and not cached:
                    restore_tree(src, a.bin, root, manifest)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print(f"{ran} blocks run, {skipped} skipped (each with its reason above), {len(failures)} failed")
    for f in failures:
        print("FAILED " + f, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
