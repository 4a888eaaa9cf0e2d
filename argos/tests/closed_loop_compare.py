#!/usr/bin/env python3
"""closed_loop.sh's comparison, row by row on the held-out half of a generated log (the rows
listed in held_out_rows).

The reading noise is the generator's (tests/diagnose_generators.hpp), restated here per kind:
  drive      the ToF's sd is 2 mm + 3 mm per metre of range (taken from the log's own reading),
             plus the whole-mm rounding's 1/12 mm^2;
  ground     N(0, 5 counts), rounded: 25 + 1/12;
  light      N(0, 15 counts), rounded: 225 + 1/12;
  proximity  N(0, 10 counts), rounded: 100 + 1/12;
  camera     N(0, 0.5 px) on each of px and py, rounded: 0.25 + 1/12 (both pooled);
  battery    N(0, sd) with sd drawn per log: the truth file's noise_sd.
Requirements (issue #20): the diagnosis replay's MSE <= 1.5 x that variance, < 0.5 x the plug-in's
replay (`default`), <= 1.05 x the calibration's (no worse, to 5 %: when the calibration fits the
effect too, e.g. a ToF offset or a ground sensor's gain, the two differ by their fits' own
scatter). For the drive the encoders' MSE is printed beside it."""
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
held_rows = [int(i) for i in open(f"{work}/held_out_rows").read().split()]
truth = json.load(open(f"{work}/truth.json"))
kind = truth["kind"]
held = [log[i] for i in held_rows]
channels = {"drive": ["tof_mm"], "ground": ["value"], "light": ["value"], "proximity": ["value"], "camera": ["px", "py"],
            "battery": ["charge"]}[kind]
unit = {"drive": "mm^2", "camera": "px^2", "battery": "charge^2"}.get(kind, "counts^2")
if kind == "drive":
    variance = sum((2.0 + 3.0 * r["tof_mm"] / 1000.0) ** 2 for r in held) / len(held) + 1.0 / 12.0
elif kind == "battery":
    variance = truth["noise_sd"] ** 2
else:
    variance = {"ground": 25.0, "light": 225.0, "proximity": 100.0, "camera": 0.25}[kind] + 1.0 / 12.0


def mse(name, chans):
    replay = rows(f"{work}/argos_{name}.csv")
    assert len(replay) == len(log), f"{name}: {len(replay)} rows, the log has {len(log)}"
    a = [replay[i] for i in held_rows]
    assert len(a) == len(held), f"{name}: {len(a)} held-out rows, the log has {len(held)}"
    return sum((x[c] - y[c]) ** 2 for x, y in zip(a, held) for c in chans) / (len(held) * len(chans))


names = ("diagnosis", "calibration", "default")
m = {n: mse(n, channels) for n in names}
print(f"{kind} {truth['cause']} {json.dumps(truth['truth'])}: {len(held)} held-out rows, {'+'.join(channels)} noise variance "
      f"(generator) {variance:.6g} {unit}")
for n in names:
    extra = f", encoder MSE {mse(n, ['left_steps']):10.2f} steps^2" if kind == "drive" else ""
    print(f"  ARGoS with the {n:11s}: MSE {m[n]:12.6g} {unit}{extra}")
bad = 0


def check(ok, msg):
    global bad
    print(("ok   " if ok else "FAIL ") + msg)
    bad += not ok


check(m["diagnosis"] <= 1.5 * variance, f"diagnosis MSE {m['diagnosis']:.6g} <= 1.5 x noise variance {1.5 * variance:.6g}")
check(m["diagnosis"] < 0.5 * m["default"], f"diagnosis MSE {m['diagnosis']:.6g} < 0.5 x the plug-in's {0.5 * m['default']:.6g}")
check(m["diagnosis"] <= 1.05 * m["calibration"],
      f"diagnosis MSE {m['diagnosis']:.6g} <= 1.05 x the calibration's {1.05 * m['calibration']:.6g}")
sys.exit(1 if bad else 0)
