#!/usr/bin/env python3
"""The expected readings of incidence.sh's cases, from the geometry alone, against ARGoS's.

PROX0's ray runs along +x at y = 0 from x = 0.49 - d (the protocol's distance d, 0.200 ... 0.235 m)
and meets the obstacle at P = (0.30, 0), at dist = d - 0.19 m (10 ... 45 mm). Each case places its
obstacle so that P is on its surface, and knows the surface's outward normal n there:
  cylinder, radius R, centre (0.30 + h, y_c), h = sqrt(R^2 - y_c^2): the ray meets the circle first
      at P; the normal is radial, n = (P - centre) / R = (-h, -y_c) / R, so cos(theta) = h / R
      (the cylinder's own yaw changes nothing: a circle turned is the same circle);
  box turned by yaw phi, its face (local axis j, side s) centred on P: the centre is
      P - s (size_j / 2) R(phi) e_j, n = s R(phi) e_j, cos(theta) = |n . x|.
The mean reading is the diagnosis's model written again here (docs/diagnose.md, proximity):
  4095 clamp01(a dist^2 + b dist + c) cos(theta)^k for dist <= range_m (0.05 m),
with the plug-in's published a, b, c = 197.8633, -30.47182, 1.011635 and k = 1.7 (incidence.sh
writes them in the file), rounded and clamped to 0..4095. Each reading must be within 1 count of it
(on another robot, whose normal the sensor takes from two side rays 1 mm away, within 3 %)
(the ray query's floating point); and each oblique case's readings must be far (> 20 counts) from
what a surface facing the sensor (cos = 1) reads, or the case would not test the normal.
  usage: incidence_check.py --xml      the cases' obstacles, one "name xml" line each
         incidence_check.py WORK_DIR   compare WORK_DIR/<case>/proximity_argos-epuck2.csv
"""
import csv
import math
import os
import sys

A, B, C, RANGE, K = 197.8633, -30.47182, 1.011635, 0.05, 1.7
PX, PY = 0.30, 0.0          # where PROX0's ray meets the obstacle
OFFSET = 0.49 - PX          # d - dist: the wall's face (0.49) to P

# (name, shape, parameters): cylinder (radius, y_centre, yaw_deg); box (size_x, size_y, yaw_deg, axis, side)
CASES = [
    ("cylinder_head_on", "cylinder", (0.03, 0.0, 0.0)),
    ("cylinder_off_axis", "cylinder", (0.03, 0.012, 0.0)),
    ("cylinder_below_axis", "cylinder", (0.03, -0.021, 0.0)),
    ("cylinder_steep", "cylinder", (0.03, 0.026, 0.0)),
    ("cylinder_grazing", "cylinder", (0.03, 0.028, 0.0)),
    ("cylinder_turned", "cylinder", (0.05, -0.03, 35.0)),
    ("box_face_20", "box", (0.02, 0.08, 20.0, 0, -1)),
    ("box_face_45", "box", (0.02, 0.08, -45.0, 0, -1)),
    ("box_face_60", "box", (0.02, 0.03, 60.0, 0, -1)),
    ("box_side_face_120", "box", (0.06, 0.06, 120.0, 1, 1)),
    # another e-puck2 (a shape ARGoS does not describe: the side rays' plane through three hits 1 mm
    # apart; its body is a circle of radius 0.035f in dynamics2d, the chord's tilt the tolerance)
    ("robot_head_on", "robot", (0.035, 0.0, 0.0)),
    ("robot_off_axis", "robot", (0.035, 0.02, 0.0)),
]
ROBOT_R = float.fromhex("0x1.1eb852p-5")  # 0.035f, the plug-in's EPUCK_RADIUS as a float


def geometry(shape, p):
    """(centre x, centre y, yaw_deg, the XML size attributes, cos(theta)) of a case."""
    if shape in ("cylinder", "robot"):
        r, yc, yaw = p
        r = ROBOT_R if shape == "robot" else r
        h = math.sqrt(r * r - yc * yc)
        nx, ny = -h / r, -yc / r
        return PX + h, yc, yaw, f'radius="{r}" height="0.1"' if shape == "cylinder" else "", abs(nx)
    sx, sy, yaw, axis, side = p
    phi = math.radians(yaw)
    e = (math.cos(phi), math.sin(phi)) if axis == 0 else (-math.sin(phi), math.cos(phi))
    n = (side * e[0], side * e[1])
    assert n[0] < 0, "the face must look at the robot"
    half = (sx if axis == 0 else sy) / 2
    return PX - half * n[0], PY - half * n[1], yaw, f'size="{sx},{sy},0.1"', abs(n[0])


def expected(dist, cos):
    base = min(max((A * dist + B) * dist + C, 0.0), 1.0) if dist <= RANGE else 0.0
    return min(max(round(4095 * base * cos ** K), 0), 4095)


if sys.argv[1:] == ["--xml"]:
    for name, shape, p in CASES:
        x, y, yaw, size, _ = geometry(shape, p)
        if shape == "robot":
            print(f'{name} <e-puck2 id="obstacle"><body position="{x:.9f},{y:.9f},0" orientation="{yaw},0,0" />'
                  f'<controller config="recorder" /></e-puck2>')
            continue
        print(f'{name} <{shape} id="obstacle" {size} movable="false"><body position="{x:.9f},{y:.9f},0" '
              f'orientation="{yaw},0,0" /></{shape}>')
    sys.exit(0)

work = sys.argv[1]
ok = True
for name, shape, p in CASES:
    cos = geometry(shape, p)[4]
    rows = list(csv.DictReader(l for l in open(os.path.join(work, name, "proximity_argos-epuck2.csv")) if not l.startswith("#")))
    worst, far, got_all, want_all = 0, 0, [], []
    for row in rows:
        dist = float(row["distance_m"]) - OFFSET
        got, want = int(row["value"]), expected(dist, cos)
        worst = max(worst, abs(got - want))
        far = max(far, abs(want - expected(dist, 1.0)))
        got_all.append(got)
        want_all.append(want)
    # the side rays' chord tilts the plane by about half the 1 mm arc (0.8 degrees on a robot): 3 %
    tolerance = [max(1, round(0.03 * w)) if shape == "robot" else 1 for w in want_all]
    good = len(rows) == 8 and all(abs(g - w) <= t for g, w, t in zip(got_all, want_all, tolerance)) and (cos > 0.999 or far > 20)
    ok = ok and good
    print(f"{'ok  ' if good else 'FAIL'} {name}: cos {cos:.4f}, {len(rows)} distances 10-45 mm, ARGoS {got_all}, "
          f"expected {want_all} (worst {worst} counts; a surface facing the sensor would read up to {far} counts apart)")
sys.exit(0 if ok else 1)
