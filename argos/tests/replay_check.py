#!/usr/bin/env python3
"""replay.sh's check: every row of ARGoS's replay (the plug-in's own implementations) against the
plug-in's published formulas, written here from the plug-in's source and docs/argos.md:
  proximity  4095 x clamp(197.8633 d^2 - 30.47182 d + 1.011635, 0, 1) for d <= 0.05 m, else 0, with
             d the log's distance_m along the sensor's axis (the plug-in ignores the angle);
  light      4095 x (1 - (I / 13.3333 / d)^2), clamped to 0..4095; 4095 (dark) beyond 0.5 m, and at
             0.5 m either (the plug-in's range, compared in floating point);
  ground     the floor's 8-bit grey round(255 g) (halves away from 0, C's lround) x 4.011764706
             (= 1023/255), rounded;
  camera     one blob per row, inside the 160 x 120 image;
  battery    the plug-in's Cubic: charge 1 at the start, falling, never below 0, and no higher than
             the log's noiseless start (the plug-in drops from full to its table's d at once).
Integers within 1 count (the plug-in's float constants and rounding). Every column but the reading
is the log's, row for row."""
import math
import sys

work = sys.argv[1]


def rows(path):
    out, head = [], None
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        cells = line.strip().split(",")
        if head is None:
            head = cells
            continue
        out.append(dict(zip(head, map(float, cells))))
    return head, out


bad = 0


def check(ok, msg):
    global bad
    print(("ok   " if ok else "FAIL ") + msg)
    bad += not ok


def expected(kind, r):
    if kind == "proximity":
        d = r["distance_m"]
        v = 197.8633 * d * d - 30.47182 * d + 1.011635 if d <= 0.05 else 0.0
        return round(4095 * min(1.0, max(0.0, v)))
    if kind == "light":
        if r["distance_m"] > 0.5 + 1e-9:
            return 4095
        return round(min(4095.0, max(0.0, 4095.0 * (1.0 - (r["intensity"] / 13.3333333333333 / r["distance_m"]) ** 2))))
    if kind == "ground":
        return round(math.floor(255 * r["grey"] + 0.5) * 4.011764706)
    return None


for kind, reading in (("proximity", ["value"]), ("light", ["value"]), ("ground", ["value"]), ("camera", ["px", "py"]),
                      ("battery", ["charge"])):
    h_log, log = rows(f"{work}/{kind}.csv")
    h_arg, arg = rows(f"{work}/{kind}.argos.csv")
    check(h_log == h_arg and len(log) == len(arg), f"{kind}: the replay has the log's header {','.join(h_log)} and its {len(log)} rows ({len(arg)})")
    same = all(x[c] == y[c] for x, y in zip(log, arg) for c in h_log if c not in reading)
    check(same, f"{kind}: every condition cell is the log's")
    if kind in ("proximity", "light", "ground"):
        off = [(y, x["value"], expected(kind, y)) for x, y in zip(arg, log)
               if not (kind == "light" and abs(y["distance_m"] - 0.5) < 1e-9 and x["value"] in (4095, expected(kind, y)))
               and abs(x["value"] - expected(kind, y)) > 1]
        sensors = sorted({int(y["sensor"]) for y in log})
        extra = f", angles {sorted({y['angle_deg'] for y in log})}" if kind == "proximity" else ""
        check(not off, f"{kind}: {len(log) - len(off)} of {len(log)} readings at the plug-in's formula within 1 count "
                       f"(sensors {sensors}{extra}){'; first off: ' + str(off[0]) if off else ''}")
    elif kind == "camera":
        check(all(0 <= x["px"] <= 159 and 0 <= x["py"] <= 119 for x in arg), f"camera: {len(arg)} blobs, each inside the image")
        # The plug-in's camera: the image's x grows to the robot's right, y downwards.
        right = [x["px"] for x, y in zip(arg, log) if y["lateral_m"] < -0.02 * y["forward_m"]]
        left = [x["px"] for x, y in zip(arg, log) if y["lateral_m"] > 0.02 * y["forward_m"]]
        check(min(right) > max(left), f"camera: LEDs to the right at px >= {min(right):.0f}, to the left at px <= {max(left):.0f}")
    else:
        q = [x["charge"] for x in arg]
        check(all(a >= b for a, b in zip(q, q[1:])) and q[-1] >= 0 and q[0] <= 1,
              f"battery: the charge falls from {q[0]} to {q[-1]} over {log[-1]['time_s']} s, never rising, never below 0")
sys.exit(1 if bad else 0)
