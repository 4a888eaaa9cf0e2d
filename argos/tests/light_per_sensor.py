#!/usr/bin/env python3
"""The light file of light_per_sensor.sh, its logs, and the checks of what ARGoS and simulate made.

usage: light_per_sensor.py write WORK_DIR    light.json, gammas.csv, noise.csv, range.json, range.csv
       light_per_sensor.py check WORK_DIR    gammas.simulated.csv, gammas.argos.csv,
                                             noise.uniform.csv, noise.gaussian.csv,
                                             range.simulated.csv, range.argos.csv

Every expected value is worked here from the file's numbers (paper Eq. 2, the noise's
distributions), apart from the project's code. Prints one line per check; exits 1 on a failure.
"""
import csv
import json
import math
import os
import sys

FULL = 4095.0
POOLED_GAMMA = 0.075                                       # m: what a sensor without its own takes
GAMMAS = [0.05, 0.06, 0.07, 0.08, 0.09, 0.10, 0.11, 0.12]  # m, sensor 0..7: their own
SDS = [1.0, 3.0, 6.0, 10.0, 20.0, 30.0, 45.0, 60.0]         # counts, sensor 0..7
GAMMA_POINT = (0.2, 1.0)   # distance_m, intensity of the noiseless check
NOISE_POINT = (0.3, 1.0)   # the same of the noisy one
READINGS = 400             # per sensor, noisy
# Eq. 2 at 0.2 m, intensity 1, by hand: (gamma I / d)^2 = (0.25, 0.30, ..., 0.60)^2
# = 0.0625, 0.09, 0.1225, 0.16, 0.2025, 0.25, 0.3025, 0.36; times 4095 subtracted from 4095:
HAND = [3839.0625, 3726.45, 3593.3625, 3439.8, 3265.7625, 3071.25, 2856.2625, 2620.8]
# The pooled gamma alone would give every sensor 4095 (1 - 0.375^2) = 3519.140625.
POOLED = 3519.140625
# The file's range_m: with 0.25 m (the plug-in's is 0.5 m) a light at 0.3 m is ignored (the reading
# is the full 4095 of no light), one at 0.2 m still counts (HAND).
RANGE_M = 0.25
RANGE_POINTS = (0.2, 0.3)
TOLERANCE = 0.15  # a spread's relative tolerance: 400 readings give it to 2.2 % (uniform) or 3.5 % (Gaussian), 1 sd


def eq2(gamma, d, i):
    return FULL * (1.0 - (gamma * i / d) ** 2)


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(l for l in f if not l.startswith("#")))


def write(work):
    rms = math.sqrt(sum(s * s for s in SDS) / len(SDS))
    light = {"kind": "light", "parameters": {"gamma": POOLED_GAMMA, "range_m": 0.5},
             "per_sensor": [{"sensor": k, "gamma": g} for k, g in enumerate(GAMMAS)],
             "noise": {"light": {"sd": rms, "per_sensor_sd": SDS, "unit": "counts"}}}
    with open(os.path.join(work, "light.json"), "w") as f:
        json.dump(light, f, indent=1)
    d, i = GAMMA_POINT
    with open(os.path.join(work, "gammas.csv"), "w") as f:
        f.write("# robot: light-per-sensor\ndistance_m,intensity,sensor,value\n")
        for k in range(8):
            f.write(f"{d},{i},{k},0\n")
    light["parameters"]["range_m"] = RANGE_M
    with open(os.path.join(work, "range.json"), "w") as f:
        json.dump(light, f, indent=1)
    with open(os.path.join(work, "range.csv"), "w") as f:
        f.write("# robot: light-per-sensor\ndistance_m,intensity,sensor,value\n")
        for d in RANGE_POINTS:
            for k in range(8):
                f.write(f"{d},1.0,{k},0\n")
    d, i = NOISE_POINT
    with open(os.path.join(work, "noise.csv"), "w") as f:
        f.write("# robot: light-per-sensor\ndistance_m,intensity,sensor,value\n")
        for _ in range(READINGS):
            for k in range(8):
                f.write(f"{d},{i},{k},0\n")


def rounded_uniform_sd(mean, half_width):
    """sd of round(mean + U), U uniform on [-half_width, half_width]: each integer's probability is
    the share of the interval that rounds to it."""
    lo, hi = mean - half_width, mean + half_width
    p = {}
    for k in range(math.floor(lo) - 1, math.ceil(hi) + 2):
        share = max(0.0, min(hi, k + 0.5) - max(lo, k - 0.5)) / (2 * half_width)
        if share > 0:
            p[k] = share
    m = sum(k * q for k, q in p.items())
    return math.sqrt(sum((k - m) ** 2 * q for k, q in p.items()))


def check(work):
    bad = 0

    def say(ok, text):
        nonlocal bad
        bad += not ok
        print(("ok   " if ok else "FAIL ") + text)

    # 1. The per-sensor gammas, noiseless: the hand values, simulate and ARGoS.
    d, i = GAMMA_POINT
    sim = {int(r["sensor"]): float(r["value"]) for r in rows(os.path.join(work, "gammas.simulated.csv"))}
    arg = {int(r["sensor"]): float(r["value"]) for r in rows(os.path.join(work, "gammas.argos.csv"))}
    for k in range(8):
        hand = HAND[k]
        say(abs(eq2(GAMMAS[k], d, i) - hand) < 1e-9, f"sensor {k}: Eq. 2 by hand {hand} (gamma {GAMMAS[k]} m)")
        say(abs(sim[k] - hand) <= 1e-6, f"sensor {k}: simulate --like {sim[k]:.6f}, by hand {hand}")
        say(abs(arg[k] - hand) <= 0.5 + 1e-6, f"sensor {k}: ARGoS {arg[k]:.0f}, by hand {hand} (rounded: within 0.5)")
        say(abs(arg[k] - sim[k]) <= 0.5 + 1e-6, f"sensor {k}: ARGoS {arg[k]:.0f} and simulate {sim[k]:.4f} agree to a count")
        say(abs(arg[k] - POOLED) > 50, f"sensor {k}: ARGoS {arg[k]:.0f} is not the pooled gamma's {POOLED}")

    # 1b. The file's range_m, noiseless: a light beyond it is not seen, one inside it is.
    for name in ("simulated", "argos"):
        got = [(float(r["distance_m"]), int(r["sensor"]), float(r["value"])) for r in rows(os.path.join(work, f"range.{name}.csv"))]
        say(len(got) == 8 * len(RANGE_POINTS), f"range {name}: {len(got)} rows, expected {8 * len(RANGE_POINTS)}")
        for d, k, v in got:
            want = FULL if d > RANGE_M else HAND[k]
            say(abs(v - want) <= 0.5 + 1e-6,
                f"range {name}: sensor {k} at {d} m with range_m {RANGE_M}: {v:.1f}, expected {want} "
                + ("(beyond the range: no light)" if d > RANGE_M else "(Eq. 2 by hand)"))

    # 2. Each sensor's own noise sd, uniform and Gaussian.
    d, i = NOISE_POINT
    for dist in ("uniform", "gaussian"):
        got = {}
        for r in rows(os.path.join(work, f"noise.{dist}.csv")):
            got.setdefault(int(r["sensor"]), []).append(float(r["value"]))
        for k in range(8):
            v = got.get(k, [])
            mean_hand = eq2(GAMMAS[k], d, i)
            # The uniform noise of the file's sd spans +-sqrt(3) sd (variance L^2/3 = sd^2); the Gaussian's
            # rounding adds 1/12 count^2 (Sheppard's correction).
            want = (rounded_uniform_sd(mean_hand, math.sqrt(3.0) * SDS[k]) if dist == "uniform"
                    else math.sqrt(SDS[k] ** 2 + 1.0 / 12.0))
            n = len(v)
            if n < READINGS:
                say(False, f"{dist} sensor {k}: {n} readings, expected {READINGS}")
                continue
            mean = sum(v) / n
            sd = math.sqrt(sum((x - mean) ** 2 for x in v) / (n - 1))
            say(abs(sd - want) <= TOLERANCE * want,
                f"{dist} sensor {k}: spread {sd:.3f} counts, its own sd {SDS[k]:g} gives {want:.3f} (within {TOLERANCE * 100:.0f} %)")
            say(abs(mean - mean_hand) <= 4 * want / math.sqrt(n) + 0.5,
                f"{dist} sensor {k}: mean {mean:.2f}, Eq. 2 by hand {mean_hand:.2f}")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    {"write": write, "check": check}[sys.argv[1]](sys.argv[2])
