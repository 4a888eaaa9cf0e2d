#!/usr/bin/env python3
"""Writes the 1M-row logs of bench/README.md's "Scale (1M rows)" section: a drive log (the robot
shuttles back and forth in front of an obstacle, 10 Hz) and a battery log (spinning at 5 cm/s,
one row per 0.1 s). Plausible values in the spec's format; only their number matters here.
    bench/scale_logs.py OUT_DIR [ROWS]"""
import math
import os
import random
import sys

out_dir = sys.argv[1]
rows = int(sys.argv[2]) if len(sys.argv) > 2 else 1_000_000
os.makedirs(out_dir, exist_ok=True)
rng = random.Random(20261123)
steps_per_m = 7763.656

with open(os.path.join(out_dir, "drive_1M.csv"), "w") as f:
    f.write("# robot: scale-test\n# obstacle_distance_m: 0.6\n")
    f.write("time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n")
    x = 0.0
    for i in range(rows):
        t = i * 0.1
        cmd = 5.0 if (i // 100) % 2 == 0 else -5.0  # 10 s forward, 10 s back
        if i:
            x += prev * 0.01 * 0.1
        prev = cmd
        steps = int(round(x * steps_per_m)) % 65536
        tof = round(1000.0 * (0.6 - x) + rng.gauss(0, 3))
        f.write(f"{t:.1f},{cmd:g},{cmd:g},{steps},{steps},{tof}\n")

with open(os.path.join(out_dir, "battery_1M.csv"), "w") as f:
    f.write("# robot: scale-test\n")
    f.write("time_s,speed_cm_s,charge,voltage_v\n")
    life = rows * 0.1
    for i in range(rows):
        t = i * 0.1
        u = t / life
        c = max(0.0, min(1.0, 1.0 - 0.1 * u - 0.6 * u ** 3 + rng.gauss(0, 0.01)))
        f.write(f"{t:.1f},5,{c:.6f},{3.4 + 0.8 * c:.4f}\n")
