#!/usr/bin/env python3
"""Hostile coefficient files against every calibrated part of the ARGoS plug-in (issue #22 item 5).

For each calibrated sensor (proximity, light, ground, camera, ToF, encoders), the wheel actuator
and the battery: a file with a parameter at 0, negative or 1e308, a noise sd of 1e308, the
camera's field of view at 0 and 360 deg and its image centre at 1e300, battery lifetimes of 0
and -100, a literal 1e999, and an unknown effect name; a misspelt section or parameter, an effect
in a robot's set, a negative camera range, a negative per-sensor light gamma, a battery table
that rises and a lifetime of 1e308. Each must stop ARGoS at Init with a
message naming the file, the line:column of the offending value and the reason.

The expected line:column come from the text this script writes, not from the plug-in: the value
is first written as a unique placeholder, whose position in the text is the expected one, and
then replaced by the hostile literal.

Then the other side of the refusal of effects ARGoS does not apply (argos/src/applied_effects.hpp):
each part runs a file with every effect of its kind on (two simulated seconds), and must not
refuse it.
    usage: hostile.py ARGOS_LIBDIR WORK_DIR
"""
import copy
import json
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
LIBDIR, WORK = sys.argv[1], os.path.join(sys.argv[2], "hostile")
os.makedirs(WORK, exist_ok=True)
FITTED = os.path.join(ROOT, "data", "fitted")
PLACEHOLDER = '"@@HOSTILE@@"'

# part: (experiment, XML element, file, [(path to a value, range reason), ...], noise channel)
PARTS = {
    "proximity": ("proximity", "epuck2_proximity", "proximity.json", "proximity"),
    "light": ("light", "epuck2_light", "light.json", "light"),
    "ground": ("ground", "epuck2_ground", "ground.json", "ground"),
    "camera": ("camera", "epuck2_colored_blob_perspective_camera", "camera.json", "camera"),
    "tof": ("drive", "epuck2_tof", "drive.json", "tof"),
    "encoder": ("drive", "epuck2_encoder", "drive.json", "encoder"),
    "actuator": ("drive", "differential_steering", "drive.json", None),
    "battery": ("battery", "epuck2_battery", "battery.json", None),
}
RANGE = "is outside its physical range"
# (case name, part, path of the value in the file, the literal written there, the reason expected)
CASES = []
for part, key in [("proximity", "range_m"), ("light", "gamma"), ("ground", "gain"), ("tof", "steps_per_m"),
                  ("encoder", "steps_per_m"), ("actuator", "steps_per_m")]:
    CASES += [(f"{part}_{key}_zero", part, ["parameters", key], "0", RANGE),
              (f"{part}_{key}_negative", part, ["parameters", key], "-7", RANGE),
              (f"{part}_{key}_1e308", part, ["parameters", key], "1e308", RANGE)]
CASES += [("proximity_a_1e308", "proximity", ["parameters", "a"], "1e308", RANGE),
          ("camera_fov_zero", "camera", ["parameters", "fov_deg"], "0", RANGE),
          ("camera_fov_360", "camera", ["parameters", "fov_deg"], "360", RANGE),
          ("camera_fov_negative", "camera", ["parameters", "fov_deg"], "-30", RANGE),
          ("camera_cx_1e300", "camera", ["parameters", "cx_px"], "1e300", RANGE),
          ("camera_cy_1e300", "camera", ["parameters", "cy_px"], "1e300", RANGE),
          ("battery_lifetime_zero", "battery", ["speeds", 3, "lifetime_s"], "0", "must be positive"),
          ("battery_lifetime_negative", "battery", ["speeds", 3, "lifetime_s"], "-100", "must be positive"),
          ("battery_slope_1e308", "battery", ["speeds", 5, "linear_slope"], "1e308", "must be negative"),
          ("battery_capacity_zero", "battery", ["effects", "capacity_scale", "k"], "0", RANGE)]
for part, (_, _, _, channel) in PARTS.items():
    if channel:
        CASES.append((f"{part}_noise_1e308", part, ["noise", channel, "sd"], "1e308", "noise sd must lie in"))
    CASES.append((f"{part}_1e999", part, None, "1e999", "too large for a double"))
    CASES.append((f"{part}_unknown_effect", part, ["effects", "warp_drive"], '{"speed": 9}', "unknown effect 'warp_drive'"))
# What ARGoS cannot apply: a covariate (no log column)
CASES.append(("proximity_covariate", "proximity", ["effects", "covariate:temperature_c"], '{"slope": 2, "centre": 25}',
              "it needs the log column 'temperature_c', which ARGoS does not have"))
CASES.append(("proximity_incidence_k_negative", "proximity", ["effects", "incidence_angle", "k"], "-1", RANGE))
CASES.append(("light_covariate", "light", ["effects", "covariate:temperature_c"], '{"slope": 2, "centre": 25}',
              "it needs the log column 'temperature_c', which ARGoS does not have"))

# Nothing dropped in silence (issue #22 item 2): a misspelt section, a misspelt parameter, an effect
# in a robot's set (None: the file's first robot), and what only ARGoS used to check.
CASES += [("proximity_misspelt_section", "proximity", ["efects"], '{"incidence_angle": {"k": 1}}', "did you mean 'effects'?"),
          ("tof_misspelt_parameter", "tof", ["parameters", "tof_scael"], "0.98", "did you mean 'tof_scale'?"),
          ("ground_robot_set_effect", "ground", ["robots", None, "effects"], '{"warp_drive": {}}', "unknown key 'effects'"),
          ("camera_range_negative", "camera", ["parameters", "range_m"], "-1", RANGE),
          ("light_per_sensor_gamma_negative", "light", ["per_sensor", 0, "gamma"], "-1", RANGE),
          ("battery_segments_rise", "battery", ["speeds", 3, "segments", 1, "y2"], "0.9", "a charge does not rise"),
          ("battery_lifetime_1e308", "battery", ["speeds", 3, "lifetime_s"], "1e308", RANGE)]


def hostile_file(part, path, literal, out):
    """Writes the part's shipped file with `literal` at `path`; returns (line, column) of it."""
    d = json.load(open(os.path.join(FITTED, PARTS[part][2])))
    if path is None:  # a literal 1e999 in place of the first base parameter or table number
        path = ["speeds", 0, "lifetime_s"] if part == "battery" else ["parameters", next(iter(d["parameters"]))]
    if path[0] == "noise":
        d["noise"][path[1]].pop("per_sensor_sd", None)  # the reader takes sd for every sensor
    if part == "battery" and path[0] == "effects":
        d["effects"] = {}
    if path[0] == "robots" and path[1] is None:
        path = ["robots", next(iter(d["robots"]))] + path[2:]
    node = d
    for k in path[:-1]:
        node = node.setdefault(k, {}) if isinstance(k, str) else node[k]
    node[path[-1]] = "@@HOSTILE@@"
    text = json.dumps(d, indent=2)
    at = text.index(PLACEHOLDER)
    line = text.count("\n", 0, at) + 1
    column = at - (text.rfind("\n", 0, at) + 1) + 1
    open(out, "w").write(text.replace(PLACEHOLDER, literal))
    return line, column


def experiment(part, coeff, out_dir):
    exp_name, element, shipped, _ = PARTS[part]
    x = open(os.path.join(ROOT, "argos", "experiments", exp_name + ".argos")).read()
    x = re.sub(r'output_dir="[^"]*"', f'output_dir="{out_dir}"', x)
    good = os.path.join(FITTED, shipped)
    x = re.sub(r'coefficients="[^"]*"', f'coefficients="{good}"', x)
    # only the part under test gets the hostile file (the battery: every robot)
    x = re.sub(rf'(<{element} [^>]*?)coefficients="[^"]*"', rf'\1coefficients="{coeff}"', x)
    path = os.path.join(out_dir, "exp.argos")
    open(path, "w").write(x)
    return path


failures = 0
env = dict(os.environ, ARGOS_PLUGIN_PATH=LIBDIR)
for name, part, path, literal, reason in CASES:
    out_dir = os.path.join(WORK, name)
    os.makedirs(out_dir, exist_ok=True)
    coeff = os.path.join(out_dir, f"{part}.json")
    line, column = hostile_file(part, path, literal, coeff)
    exp = experiment(part, coeff, out_dir)
    try:
        r = subprocess.run(["argos3", "-n", "-z", "-c", exp], env=env, capture_output=True, text=True, timeout=120)
        log, code = r.stdout + r.stderr, r.returncode
    except subprocess.TimeoutExpired:
        log, code = "timed out: ARGoS ran on", 0
    where = f"{coeff}:{line}:{column}"
    message = next((l for l in log.splitlines() if where in l), "")
    ok = code != 0 and where in log and reason in log
    failures += not ok
    print(f"{'ok  ' if ok else 'FAIL'} {name}: {message.strip()[:260] if ok else ''}")
    if not ok:
        print(f"     expected exit != 0 (got {code}), '{where}' and '{reason}' in:\n" + log[-1500:])
print(f"{len(CASES) - failures} of {len(CASES)} hostile files stopped ARGoS at Init with the file, line:column and reason")

# The other side of "ARGoS refuses a non-neutral effect it does not apply" (applied_effects.hpp):
# a file with every effect of its kind's catalogue on, each away from its neutral value, runs in
# the part that reads it (the values are this script's, inside each documented range). A part
# whose list missed an effect it runs would stop here with "does not apply it in ARGoS".
EVERY_EFFECT = {
    "proximity": ({"ambient_offset": {"offset": 10.0}, "sensor_gain": {"gains": [1.1] * 8},
                   "long_tail": {"amplitude": 50.0, "length_m": 0.02}, "incidence_angle": {"k": 1.0},
                   "saturation": {"level": 4000.0}}, {}),
    "light": ({"ambient_offset": {"offset": 10.0}, "falloff_exponent": {"exponent": 2.2},
               "sensor_gain": {"gains": [1.05] * 8}}, {}),
    "ground": ({"nonlinear_response": {"exponent": 1.3}}, {}),
    "camera": ({"radial_distortion": {"k1": -0.1}, "distortion_k2": {"k2": 1.0}, "distortion_k3": {"k3": 5.0}}, {}),
    "battery": ({"capacity_scale": {"k": 0.9}}, {}),
}
DRIVE_EFFECTS = ({"speed_limit": {"max_cm_s": 12.0}, "accel_limit": {"accel_cm_s2": 40.0}, "speed_scale": {"k": 0.95},
                  "latency": {"delay_s": 0.05}},
                 {"slip_time_constant_s": 0.1, "tof_offset_mm": 5.0, "tof_scale": 1.02})
for part in ("tof", "encoder", "actuator"):
    EVERY_EFFECT[part] = DRIVE_EFFECTS
refused = 0
for part, (effects, parameters) in EVERY_EFFECT.items():
    out_dir = os.path.join(WORK, f"{part}_every_effect")
    os.makedirs(out_dir, exist_ok=True)
    coeff = os.path.join(out_dir, f"{part}.json")
    d = json.load(open(os.path.join(FITTED, PARTS[part][2])))
    d["effects"] = copy.deepcopy(effects)
    d.setdefault("parameters", {}).update(parameters)
    json.dump(d, open(coeff, "w"), indent=2)
    exp = experiment(part, coeff, out_dir)
    x = re.sub(r'<experiment length="[^"]*"', '<experiment length="2"', open(exp).read())
    open(exp, "w").write(x)
    try:
        r = subprocess.run(["argos3", "-n", "-z", "-c", exp], env=env, capture_output=True, text=True, timeout=120)
        log, code = r.stdout + r.stderr, r.returncode
    except subprocess.TimeoutExpired:
        log, code = "timed out", -1
    ok = code == 0 and "does not apply it in ARGoS" not in log
    refused += not ok
    print(f"{'ok  ' if ok else 'FAIL'} {part}_every_effect: {', '.join(list(effects) + list(parameters))} "
          f"{'applied' if ok else 'refused or failed (exit ' + str(code) + ')'}")
    if not ok:
        print(log[-1500:])
print(f"{len(EVERY_EFFECT) - refused} of {len(EVERY_EFFECT)} parts ran a file with every effect of their kind on")
sys.exit(1 if failures or refused else 0)
