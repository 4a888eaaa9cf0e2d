#!/usr/bin/env python3
"""Checks that ARGoS's calibrated sensors draw the coefficient file's reading noise.

usage: noise_sd.py KIND NOISELESS_DIR NOISY_DIR COEFFICIENT_FILE

The same protocol recorded twice with the same seed, once with noise="false" and once with
noise="true": the trajectories and geometry are the same (the protocols are driven by time, not by
readings), so a reading's noise is the noisy reading minus the noiseless one. Its standard
deviation must lie within 10 % of the file's noise.<channel>.sd (per sensor where the file has
per_sensor_sd). Readings whose noiseless value lies within 4 sd of a rail are left out (the rail
clips the noise there). KIND: proximity, ground, light, drive (the ToF).
Prints one line per channel and sensor; exits 1 when any is out of tolerance.
"""
import csv
import glob
import json
import math
import os
import sys

# kind -> (channel, value column, rails)
KINDS = {
    "proximity": ("proximity", "value", (0, 4095)),
    "ground": ("ground", "value", (0, 1023)),
    "light": ("light", "value", (0, 4095)),
    "drive": ("tof", "tof_mm", (20, 2000)),
}
TOLERANCE = 0.10


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(l for l in f if not l.startswith("#")))


def main():
    kind, quiet_dir, noisy_dir, coefficients = sys.argv[1:5]
    channel, column, (low, high) = KINDS[kind]
    noise = json.load(open(coefficients))["noise"][channel]
    per_sensor = noise.get("per_sensor_sd")
    diffs = {}  # sensor -> differences
    files = sorted(glob.glob(os.path.join(quiet_dir, "*.csv")))
    if not files:
        sys.exit(f"no logs in {quiet_dir}")
    for q in files:
        n = os.path.join(noisy_dir, os.path.basename(q))
        rq, rn = rows(q), rows(n)
        if len(rq) != len(rn):
            sys.exit(f"{n}: {len(rn)} rows, the noiseless log has {len(rq)}")
        for a, b in zip(rq, rn):
            sensor = int(a.get("sensor", 0))
            sd = per_sensor[sensor] if per_sensor else noise["sd"]
            quiet = float(a[column])
            if quiet - 4 * sd <= low or quiet + 4 * sd >= high:
                continue
            diffs.setdefault(sensor, []).append(float(b[column]) - quiet)
    bad = 0
    for sensor, d in sorted(diffs.items()):
        want = per_sensor[sensor] if per_sensor else noise["sd"]
        mean = sum(d) / len(d)
        got = math.sqrt(sum((x - mean) ** 2 for x in d) / (len(d) - 1))
        ok = abs(got - want) <= TOLERANCE * want and len(d) >= 100
        bad += not ok
        print(f"{'ok  ' if ok else 'FAIL'} {channel} sensor {sensor}: {len(d)} readings, noise sd {got:.4g} {noise['unit']}, "
              f"file {want:.4g} (|diff| {abs(got - want) / want * 100:.1f} % <= {TOLERANCE * 100:.0f} %), mean {mean:+.3g}")
    sys.exit(1 if bad or not diffs else 0)


if __name__ == "__main__":
    main()
