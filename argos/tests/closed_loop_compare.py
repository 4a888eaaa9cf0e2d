#!/usr/bin/env python3
"""closed_loop.sh's comparison, row by row on the held-out half of a generated drive log.

The reading noise is the generator's (tests/diagnose_generators.hpp, drive_log): the ToF's sd is
2 mm + 3 mm per metre of range, plus the whole-mm rounding's 1/12 mm^2; the range is taken from
the log's own reading. Requirements (issue #20): the diagnosis replay's ToF MSE <= 1.5 x that
variance, < 0.5 x the plug-in's replay (`default`), <= 1.05 x the calibration's (no worse, to 5 %:
when the calibration fits the effect too, e.g. a ToF offset, the two differ by their fits' own
scatter). The encoders' MSE is printed beside it."""
import json, sys

work = sys.argv[1]


def rows(path):
    out = []
    head = None
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        cells = line.strip().split(",")
        if head is None:
            head = cells
            continue
        out.append(dict(zip(head, map(float, cells))))
    return out


log = rows(f"{work}/full.csv")
start = int(open(f"{work}/held_out_from").read())
truth = json.load(open(f"{work}/truth.json"))
held = log[start:]
variance = sum((2.0 + 3.0 * r["tof_mm"] / 1000.0) ** 2 for r in held) / len(held) + 1.0 / 12.0


def mse(name, channel):
    a = rows(f"{work}/argos_{name}.csv")[start:]
    assert len(a) == len(held), f"{name}: {len(a)} held-out rows, the log has {len(held)}"
    return sum((x[channel] - y[channel]) ** 2 for x, y in zip(a, held)) / len(held)


m = {n: mse(n, "tof_mm") for n in ("diagnosis", "calibration", "default")}
s = {n: mse(n, "left_steps") for n in ("diagnosis", "calibration", "default")}
print(f"{truth['cause']} {json.dumps(truth['truth'])}: {len(held)} held-out rows, ToF noise variance "
      f"(generator) {variance:.2f} mm^2")
for n in m:
    print(f"  ARGoS with the {n:11s}: ToF MSE {m[n]:10.2f} mm^2, encoder MSE {s[n]:10.2f} steps^2")
bad = 0


def check(ok, msg):
    global bad
    print(("ok   " if ok else "FAIL ") + msg)
    bad += not ok


check(m["diagnosis"] <= 1.5 * variance, f"diagnosis MSE {m['diagnosis']:.2f} <= 1.5 x noise variance {1.5 * variance:.2f}")
check(m["diagnosis"] < 0.5 * m["default"], f"diagnosis MSE {m['diagnosis']:.2f} < 0.5 x the plug-in's {0.5 * m['default']:.2f}")
check(m["diagnosis"] <= 1.05 * m["calibration"],
      f"diagnosis MSE {m['diagnosis']:.2f} <= 1.05 x the calibration's {1.05 * m['calibration']:.2f}")
sys.exit(1 if bad else 0)
