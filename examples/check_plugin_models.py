#!/usr/bin/env python3
"""Checks examples/plugin_models.cpp's output (CTest: example_plugin_models).

Every number the example prints is recomputed here from the coefficient files in data/fitted by
the formulas the documentation gives (docs/coefficient-files.md, "Per kind"; docs/battery-models.md
for the corrected Cubic), without the C++ models or the generated header: the example, the header
and the models must all agree with the JSON files. Readings drawn with noise are checked to lie
within 6 noise sd (the file's `noise` section) of the expected value.

    check_plugin_models.py --exe build/bin/example_plugin_models --fitted data/fitted
"""
import argparse
import json
import math
import os
import subprocess
import sys

FULL_SCALE = 4095.0  # proximity and light register
GROUND_FULL_SCALE = 1023.0
TOF_MIN_MM, TOF_MAX_MM = 20.0, 2000.0
# The firmware's 0.8/0.2 moving average every 0.5 s as a time constant: 0.5 / ln(1.25) = 2.24071 s
# (the model writes it to five digits, 2.2407 s: the battery's tolerance below covers the
# difference, about 1e-8 a tick).
FIRMWARE_FILTER_TAU_S = 0.5 / math.log(1.25)


def load(folder, kind):
    with open(os.path.join(folder, kind + ".json")) as f:
        return json.load(f)


def clamp(v, lo, hi):
    return min(max(v, lo), hi)


def expected(folder):
    """name -> (value, tolerance, kind of check)."""
    out = {}
    # Proximity, Eq. 1: reading / 4095 = a d^2 + b d + c (clamped to 0..1) for d <= range.
    j = load(folder, "proximity")
    p = j["parameters"]
    d = 0.02
    mean = FULL_SCALE * clamp(p["a"] * d * d + p["b"] * d + p["c"], 0.0, 1.0) if d <= p["range_m"] else 0.0
    sd = j["noise"]["proximity"]["per_sensor_sd"][0]
    out["proximity_mean"] = (mean, 1e-9 * FULL_SCALE, "value")
    out["proximity_reading"] = (mean, 6 * sd, "noisy", 0.0, FULL_SCALE)

    # Light, Eq. 2: reading / 4095 = 1 - (gamma I / d)^2 for d <= range, gamma sensor 0's own
    # where the calibration fitted one (per_sensor), else the common one.
    j = load(folder, "light")
    g = j["parameters"]["gamma"]
    g = next((e["gamma"] for e in j.get("per_sensor", []) if e["sensor"] == 0 and "gamma" in e), g)
    intensity, d = 1.0, 0.20
    mean = FULL_SCALE * (1.0 - (g * intensity / d) ** 2)
    sd = j["noise"]["light"]["per_sensor_sd"][0]
    out["light_mean"] = (mean, 1e-9 * FULL_SCALE, "value")
    out["light_reading"] = (mean, 6 * sd, "noisy", 0.0, FULL_SCALE)

    # Ground: value = offset + gain grey, per sensor (1: centre).
    j = load(folder, "ground")
    p = j["parameters"]
    mean = p["offset"][1] + p["gain"][1] * 0.5
    sd = j["noise"]["ground"]["per_sensor_sd"][1]
    out["ground_mean"] = (mean, 1e-9 * GROUND_FULL_SCALE, "value")
    out["ground_reading"] = (mean, 6 * sd, "noisy", 0.0, GROUND_FULL_SCALE)

    # Camera: px = cx - f lateral/forward, py = cy - f vertical/forward, f = 80 / tan(fov/2).
    j = load(folder, "camera")
    p = j["parameters"]
    f = (p["width_px"] / 2.0) / math.tan(math.radians(p["fov_deg"]) / 2.0)
    fwd, lat, up = 0.50, 0.05, 0.02
    px, py = p["cx_px"] - f * lat / fwd, p["cy_px"] - f * up / fwd
    sd = j["noise"]["camera"]["sd"]
    out["camera_px_mean"] = (px, 1e-9 * abs(px), "value")
    out["camera_py_mean"] = (py, 1e-9 * abs(py), "value")
    out["camera_px_reading"] = (px, 6 * sd, "noisy", -1e9, 1e9)
    out["camera_py_reading"] = (py, 6 * sd, "noisy", -1e9, 1e9)

    # Drive: tof_mm = scale 1000 (D - travel) + offset, the body's travel lagging the wheels by a
    # first-order lag of time constant tau (from rest at a constant wheel speed v:
    # travel = v (t - tau (1 - exp(-t/tau)))); encoders floor(steps_per_m v t). Registers: the
    # ToF rounded and clamped to its 20..2000 mm rails. No noise: the expected registers.
    j = load(folder, "drive")
    p = j["parameters"]
    v, obstacle = 0.05, 0.30
    tau = p["slip_time_constant_s"]
    for k in range(11):
        t = 0.1 * k
        travel = v * (t - tau * (1.0 - math.exp(-t / tau))) if tau > 0 else v * t
        tof = p["tof_scale"] * 1000.0 * (obstacle - travel) + p["tof_offset_mm"]
        out["drive_tof_mm_%d" % k] = (clamp(tof, TOF_MIN_MM, TOF_MAX_MM), 0.5 + 1e-6, "register")
        # floor: the register may sit one below where the product lies within rounding of an integer
        out["drive_left_steps_%d" % k] = (p["steps_per_m"] * v * t, 0.0, "floor")

    # Battery, corrected Cubic at a table speed (docs/battery-models.md): above the curve's
    # intercept d the excess x = charge - d follows x' = -x/tau + c (the firmware filter's time
    # constant, the curve's initial slope c): from full, x(t) = c tau + (1 - d - c tau) e^(-t/tau),
    # in closed form whatever the ticks; it reaches 0 at t* = tau ln((1 - d - c tau)/(-c tau)), and
    # from there the charge is the curve a t^3 + b t^2 + c t + d at t - t* (0 past the lifetime).
    j = load(folder, "battery")
    row = next(s for s in j["speeds"] if abs(s["speed_cm_s"] - 5.0) < 1e-9)
    d0, c1, b2, a3 = row["cubic"]
    end = row["lifetime_s"]

    def cubic(t):
        return ((a3 * t + b2) * t + c1) * t + d0

    c_tau = c1 * FIRMWARE_FILTER_TAU_S
    t_star = FIRMWARE_FILTER_TAU_S * math.log((1.0 - d0 - c_tau) / -c_tau)
    checkpoints = {}
    for n in (1, 600, 36000):
        t = 0.1 * n
        if t < t_star:
            checkpoints[n] = d0 + c_tau + (1.0 - d0 - c_tau) * math.exp(-t / FIRMWARE_FILTER_TAU_S)
        else:
            checkpoints[n] = cubic(t - t_star) if t - t_star < end else 0.0
    for n, value in checkpoints.items():
        out["battery_charge_%d" % n] = (value, 1e-6, "value")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", required=True)
    ap.add_argument("--fitted", required=True, help="the folder of the coefficient files (data/fitted)")
    args = ap.parse_args()
    run = subprocess.run([args.exe], capture_output=True, text=True)
    if run.returncode != 0:
        print("the example exited %d: %s" % (run.returncode, run.stderr))
        return 1
    printed = {}
    for line in run.stdout.splitlines():
        name, _, value = line.partition(" = ")
        printed[name] = float(value)
    want = expected(args.fitted)
    failures = []
    for name, spec in want.items():
        if name not in printed:
            failures.append("%s: not printed" % name)
            continue
        got, value, tol, how = printed[name], spec[0], spec[1], spec[2]
        if how == "value" or how == "register":
            ok = abs(got - value) <= tol
        elif how == "floor":
            ok = got == math.floor(value) or (abs(value - round(value)) < 1e-6 and got == round(value) - 1)
        else:  # noisy: an integer register within the rails and within 6 sd of the mean
            lo, hi = spec[3], spec[4]
            ok = got == int(got) and lo <= got <= hi and abs(got - clamp(value, lo, hi)) <= tol + 0.5
        print("%-22s printed %-16.12g expected %-16.12g %s" % (name, got, value, "ok" if ok else "FAILED"))
        if not ok:
            failures.append(name)
    extra = sorted(set(printed) - set(want))
    if extra:
        failures.append("printed but not checked: " + ", ".join(extra))
    if failures:
        print("FAILED: " + "; ".join(failures))
        return 1
    print("all %d values agree with %s" % (len(want), args.fitted))
    return 0


if __name__ == "__main__":
    sys.exit(main())
