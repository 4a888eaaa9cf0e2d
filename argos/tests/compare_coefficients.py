#!/usr/bin/env python3
"""Checks a refitted coefficient file against a reference.

usage: compare_coefficients.py KIND REFIT.json (REFERENCE.json | plugin)
       compare_coefficients.py KIND REFIT.json TRUTH.json --own-se K

Every coefficient of REFIT must lie within the reference's standard error of the reference value,
or within the stated tolerance below where ARGoS's geometry or the readings' quantisation make the
standard error unreachable. `plugin` compares with the E-Puck2 plug-in's published coefficients.
With --own-se K, TRUTH.json is the file ARGoS ran (its values are the truth) and every parameter of
REFIT, and every effect parameter of a diagnosis REFIT, must lie within K of REFIT's own standard
errors (std_errors; a finding's uncertainty), with no stated tolerance: for the camera recorded
with its pixel noise on (argos/tests/roundtrip.sh camera). K = 2: a parameter within 2 standard
errors holds 95 % of the time for a Gaussian estimate; 1 would fail about a third of the
parameters of a correct refit, and the recording is seeded, so the outcome is fixed.
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
#  camera: no stated tolerance. Its round trip records with the calibrated pixel noise on (0.58
#          px), which dithers ARGoS's whole-pixel rounding as a real camera's noise does, and
#          compares with --own-se 2. (Noiseless, every frame of a grid position rounds the same way:
#          that bias is not averaged out and moved the centre by a few hundredths of a pixel and the
#          field of view by a few hundredths of a degree, beyond the standard errors.)
TOLERANCE = {
    "proximity": {"a": 0.5, "b": 0.02, "c": 0.0003},
    "ground": {"gain": 0.75, "offset": 0.5},
    "drive": {"steps_per_m": 4.0, "tof_scale": 0.0015, "tof_offset_mm": 0.5, "slip_time_constant_s": 0.015},
    "light": {"gamma": 5e-5},
    "camera": {},
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


def check(name, got, want, se, tol, ref_label="reference", why=None):
    bad = 0
    for i, (g, w) in enumerate(zip(as_list(got), as_list(want))):
        s = as_list(se)[i] if se is not None else 0.0
        allowed = max(s, tol)
        ok = abs(g - w) <= allowed
        bad += not ok
        label = name if not isinstance(got, list) else f"{name}[{i}]"
        print(f"{'ok  ' if ok else 'FAIL'} {label}: refit {g:.10g}, {ref_label} {w:.10g}, |diff| {abs(g - w):.3g} "
              f"<= {allowed:.3g} ({why or ('std error' if s >= tol else 'stated tolerance')})")
    return bad


def own_se(kind, refit, truth, k):
    """Every parameter (and effect parameter) of refit within k of refit's own standard errors."""
    bad = 0
    se = refit.get("std_errors", {})
    for name, value in refit["parameters"].items():
        if name in NOT_COMPARED.get(kind, {}):
            print(f"skip {name}: {NOT_COMPARED[kind][name]}")
        elif name not in se:
            # A diagnosis's base (fov_deg refitted with the effects) carries no standard error.
            print(f"skip {name}: the refit gives no standard error (refit {value:.10g}, "
                  f"truth {truth['parameters'].get(name, float('nan')):.10g})")
        else:
            bad += check(name, value, truth["parameters"][name], k * se[name], 0.0, "truth", f"{k:g} x the refit's std error")
    found = {f["cause"]: f.get("uncertainty", {}) for f in refit.get("findings", [])}
    for cause, params in truth.get("effects", {}).items():
        if cause not in refit.get("effects", {}):
            print(f"FAIL {cause}: in the truth, not found by the refit")
            bad += 1
            continue
        for name, want in params.items():
            bad += check(f"{cause}.{name}", refit["effects"][cause][name], want,
                         k * found.get(cause, {}).get(name, 0.0), 0.0, "truth",
                         f"{k:g} x the refit's std error")
    return bad


def main():
    if len(sys.argv) == 6 and sys.argv[4] == "--own-se":
        kind, refit_path, truth_path, k = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[5])
        sys.exit(1 if own_se(kind, json.load(open(refit_path)), json.load(open(truth_path)), k) else 0)
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
