#!/usr/bin/env python3
"""Compares ARGoS's protocol recordings (closed_loop_sensors.sh) with the generator's truth.

The expected mean reading of each condition is the generator's formula (tests/diagnose_generators.hpp,
written again here) with its drawn parameters (truth.json):
  proximity: min(4095 clamp01(cos(theta)^k (a d^2 + b d + c)) [d <= 0.05] + offset + amplitude exp(-d / length), level),
             a, b, c the plug-in's published 197.8633, -30.47182, 1.011635 (the generator's base);
             theta 0, or 30 deg for incidence_angle, whose protocol turns the wall by 30 deg (the
             ray then meets it 0.01 (1 - 1 / cos 30) m short of the nominal distance d);
  light:     4095 (1 - (gamma I / d)^p) - offset, gamma the generator's draw.
rounded and clamped to 0..4095 as the register. Required: the diagnosis recording's RMS error over
the conditions at most the generator's reading noise sd (10 counts proximity, 15 light), and, when
the effect is large enough to matter, below half the plug-in's.
"""
import csv
import glob
import json
import math
import os
import sys

work = sys.argv[1]
t = json.load(open(os.path.join(work, "truth.json")))
kind, cause, truth = t["kind"], t["cause"], t["truth"]
clamp = lambda v: min(max(round(v), 0), 4095)


def expected(row):
    d = float(row["distance_m"])
    if kind == "proximity":
        base, k = 0.0, truth.get("k", 0.0)
        cos = 1.0
        if cause == "incidence_angle":  # the wall turned by 30 degrees (closed_loop_sensors.sh)
            cos = math.cos(math.radians(30.0))
            d = d + 0.01 - 0.01 / cos
        if d <= 0.05:
            base = 4095 * min(max(cos ** k * ((197.8633 * d - 30.47182) * d + 1.011635), 0.0), 1.0)
        tail = truth.get("amplitude", 0.0) * math.exp(-d / truth.get("length_m", 0.02))
        return clamp(min(base + truth.get("offset", 0.0) + tail, truth.get("level", 1e9)))
    gamma, i = t["generator_gamma_m"], float(row["intensity"])
    return clamp(4095 * (1 - (gamma * i / d) ** truth.get("exponent", 2.0)) - truth.get("offset", 0.0))


def rms(folder):
    err, n, worst = 0.0, 0, (0, None)
    for path in sorted(glob.glob(os.path.join(work, folder, "*.csv"))):
        for row in csv.DictReader(l for l in open(path) if not l.startswith("#")):
            e = float(row["value"]) - expected(row)
            err += e * e
            n += 1
            if abs(e) > abs(worst[0]):
                worst = (e, {k: row[k] for k in row if k != "value"})
    return math.sqrt(err / n), n, worst


noise = 10.0 if kind == "proximity" else 15.0
diag, n, worst = rms("argos_diagnosis")
plugin, _, _ = rms("argos_plugin")
print(f"{kind} {cause} (truth {truth}): ARGoS with the diagnosis reads the generator's truth within RMS {diag:.2f} counts "
      f"over {n} readings (worst {worst[0]:+.0f} at {worst[1]}); the plug-in's own: RMS {plugin:.2f}; noise sd {noise:g}")
ok = diag <= noise and (not t["parameters_matter"] or diag < 0.5 * plugin)
print("ok" if ok else "FAIL")
sys.exit(0 if ok else 1)
