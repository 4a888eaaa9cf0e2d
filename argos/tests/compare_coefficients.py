#!/usr/bin/env python3
"""Checks a refitted coefficient file against a reference.

usage: compare_coefficients.py KIND REFIT.json (REFERENCE.json | plugin)

Every coefficient of REFIT must lie within the reference's standard error of the reference value,
or within the stated tolerance below where ARGoS's geometry or the readings' quantisation make the
standard error unreachable. `plugin` compares with the E-Puck2 plug-in's published coefficients.
Prints one line per coefficient; exits 1 when any is out of tolerance.
"""
import json
import sys

# Stated tolerances (absolute), used when larger than the reference's standard error.
#  proximity: readings are 12-bit counts (1/4095 of full scale), the fit is exact otherwise.
#  ground: readings are integer counts (+-0.5); ARGoS's floor colours are 8-bit.
#  drive: steps are whole (floor), over 0.22 m runs: 0.5 step / 0.22 m; the ToF reads whole mm
#         (+-0.5 mm over the 0.08-0.52 m the runs span: about 0.0011 on the scale, 0.5 mm offset).
#         The calibrated actuator caps the 15 cm/s runs at the firmware's 1100 steps/s over the
#         file's steps_per_m (14.175 cm/s at 7760), where the calibration takes the cap as 1100
#         steps/s over the plug-in's 7763.656 (14.168 cm/s): 0.05 % on the capped rows, 2.5 measured
#         steps/m on the pooled steps_per_m, hence 4 steps/m. The slip comes back through
#         dynamics2d, whose force-limited velocity control moves the body by less than it is told
#         on every tick whose speed changes: a lag of its own of about 0.012 s (measured:
#         argos/tests/actuator.sh, 0.312 s for a file's 0.3 s), hence 0.015 s.
#  battery: rows every 10 s; the lifetime is the last tick with charge left.
#  light: 12-bit counts.
#  camera: whole pixels, noiseless, every frame of a grid position the same: the rounding (+-0.5 px)
#          is not averaged out as the robot's noise dithers it; over the grid's 190 positions it
#          moves the centre by a few hundredths of a pixel and the field of view (f = 290 px) by a
#          few hundredths of a degree, hence 0.1 px and 0.05 deg.
TOLERANCE = {
    "proximity": {"a": 0.5, "b": 0.02, "c": 0.0003},
    "ground": {"gain": 0.75, "offset": 0.5},
    "drive": {"steps_per_m": 4.0, "tof_scale": 0.0015, "tof_offset_mm": 0.5, "slip_time_constant_s": 0.015},
    "light": {"gamma": 5e-5},
    "camera": {"cx_px": 0.1, "cy_px": 0.1, "fov_deg": 0.05},
    "battery": {},
}
PLUGIN = {
    "proximity": {"a": 197.8633, "b": -30.47182, "c": 1.011635},
    "ground": {"gain": [1023.0] * 3, "offset": [0.0] * 3},
    "drive": {"tof_scale": 1.0, "tof_offset_mm": 0.0, "steps_per_m": 7763.656},
    "light": {"gamma": 1.0 / 13.3333333333333},
}
# Not compared, with the reason printed.
NOT_COMPARED = {
    "proximity": {"mean_a": "means of noiseless readings equal the maxima", "mean_b": "idem", "mean_c": "idem",
                  "range_m": "geometry, not fitted"},
    "light": {"range_m": "geometry, not fitted"},
    "camera": {"aperture_deg": "ARGoS's aperture, computed from fov_deg", "width_px": "the image's size, not fitted",
               "height_px": "the image's size, not fitted", "range_m": "geometry, not fitted"},
}


def as_list(v):
    return v if isinstance(v, list) else [v]


def check(name, got, want, se, tol):
    bad = 0
    for i, (g, w) in enumerate(zip(as_list(got), as_list(want))):
        s = as_list(se)[i] if se is not None else 0.0
        allowed = max(s, tol)
        ok = abs(g - w) <= allowed
        bad += not ok
        label = name if not isinstance(got, list) else f"{name}[{i}]"
        print(f"{'ok  ' if ok else 'FAIL'} {label}: refit {g:.10g}, reference {w:.10g}, |diff| {abs(g - w):.3g} "
              f"<= {allowed:.3g} ({'std error' if s >= tol else 'stated tolerance'})")
    return bad


def main():
    kind, refit_path, ref = sys.argv[1], sys.argv[2], sys.argv[3]
    refit = json.load(open(refit_path))
    tol = TOLERANCE[kind]
    bad = 0
    if kind == "battery":
        reference = json.load(open(ref))
        for s, (r, w) in enumerate(zip(refit["speeds"], reference["speeds"])):
            for k, name in enumerate(["d", "c", "b", "a"]):
                bad += check(f"speed {s} cubic {name}", r["cubic"][k], w["cubic"][k], w["cubic_std_errors"][k], 0.0)
            bad += check(f"speed {s} lifetime_s", r["lifetime_s"], w["lifetime_s"], w["lifetime_std_error_s"], 0.2)
        sys.exit(1 if bad else 0)
    if kind == "light" and ref != "plugin":
        reference = json.load(open(ref))
        per = {e["sensor"]: e for e in reference.get("per_sensor", [])}
        if per:
            # The calibrated sensor uses the per-sensor gammas when the file has them: those are
            # what must come back. The common gamma is then a blend of the two that depends on
            # which readings each protocol censors, so it is not compared.
            print("skip gamma: the file's per_sensor gammas are what the calibrated sensor uses")
            for e in refit.get("per_sensor", []):
                w = per.get(e["sensor"])
                if w is None:
                    print(f"skip per_sensor {e['sensor']}: not in the reference")
                    continue
                bad += check(f"gamma of sensor {e['sensor']}", e["gamma"], w["gamma"], w["std_error"], 0.0)
            sys.exit(1 if bad else 0)
    if ref == "plugin":
        want, se = PLUGIN[kind], {}
    else:
        reference = json.load(open(ref))
        want, se = reference["parameters"], reference.get("std_errors", {})
    for name, value in refit["parameters"].items():
        if name in NOT_COMPARED.get(kind, {}):
            print(f"skip {name}: {NOT_COMPARED[kind][name]}")
            continue
        if name not in want:
            print(f"skip {name}: no reference value")
            continue
        bad += check(name, value, want[name], se.get(name), tol.get(name, 0.0))
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
