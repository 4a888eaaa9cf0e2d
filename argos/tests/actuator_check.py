#!/usr/bin/env python3
"""Checks actuator.sh's ARGoS drive logs against the effects' closed forms (docs/diagnose.md,
"drive"), written here apart from the code under test:
  cap    wheels at min(command, 1100 steps/s / steps_per_m): the encoders count 1100 steps/s;
  accel  wheel travel a t^2 / 2 until the command's speed u is reached at t = u / a, then u t - u^2 / 2a;
  slip   body travel u (t - tau (1 - exp(-t / tau))), the wheels' u t: the lag tends to u tau;
  still  with encoder noise on, every row standing still reads exactly the count it read before.
A row k of a run holds the readings after k ticks (0.1 s) and the command for the next tick."""
import glob, json, math, os, sys

WORK = sys.argv[1]
TICK = 0.1
failures = []


def check(ok, msg):
    print(("ok   " if ok else "FAIL ") + msg)
    if not ok:
        failures.append(msg)


def rows(name, direction="toward"):
    path = glob.glob(os.path.join(WORK, name, f"drive_{direction}_*.csv"))[0]
    out = []
    for line in open(path):
        if line[0].isdigit():
            t, l, r, ls, rs, tof = line.strip().split(",")
            out.append((float(t), float(l), int(ls), int(rs), int(tof)))
    return out


def onset(rs):
    """The first row whose command is not 0: motion is seen from the next row on."""
    return next(k for k, r in enumerate(rs) if r[1] != 0)


def params(name):
    return json.load(open(os.path.join(WORK, name + ".json")))["parameters"]


# cap: steady wheel speed from the encoders over the moving rows (after the first tick)
p = params("cap")
spm = p["steps_per_m"]
rs = rows("cap")
k0 = onset(rs)
moving = [r for k, r in enumerate(rs) if k > k0 and rs[k - 1][1] != 0]
rate = (moving[-1][2] - moving[0][2]) / (moving[-1][0] - moving[0][0])
check(abs(rate - 1100) <= 11, f"cap: a 20 cm/s command counts {rate:.1f} steps/s (firmware cap 1100; "
      f"{100 * 1100 / spm:.3f} cm/s at steps_per_m {spm:.2f})")
rs = rows("default")
k0 = onset(rs)
moving = [r for k, r in enumerate(rs) if k > k0 and rs[k - 1][1] != 0]
rate_default = (moving[-1][2] - moving[0][2]) / (moving[-1][0] - moving[0][0])
check(abs(rate_default - 0.2 * 7763.656) <= 16, f"cap: the plug-in's default actuator runs the same command at "
      f"{rate_default:.1f} steps/s (20 cm/s: {0.2 * 7763.656:.1f}; the robot cannot)")
# ToF over the capped run: the body moves at the cap too
rs = rows("cap")
k0 = onset(rs)
moving = [r for k, r in enumerate(rs) if k > k0 and rs[k - 1][1] != 0]
tof_rate = -(moving[-1][4] - moving[0][4]) / (moving[-1][0] - moving[0][0]) / p["tof_scale"] / 1000
check(abs(tof_rate * 100 - 110000 / spm) <= 0.2, f"cap: the body (ToF) moves at {tof_rate * 100:.2f} cm/s")

# accel: 10 cm/s, a = 50 cm/s^2 (0.5 m/s^2), ramp 0.2 s
u, a = 0.10, 0.5
rs = rows("accel")
k0 = onset(rs)
worst = 0
for k in range(k0 + 1, k0 + 8):
    t = (k - k0) * TICK
    x = a * t * t / 2 if t <= u / a else u * t - u * u / (2 * a)
    want = math.floor(spm * x)
    worst = max(worst, abs(rs[k][2] - want))
check(worst <= 1, f"accel: 7 rows after a 10 cm/s step with accel_limit 50 cm/s^2, the encoders within {worst} "
      f"step of floor(steps_per_m a t^2/2) (ramp 0.2 s: {math.floor(spm * 0.0025)} steps at 0.1 s, "
      f"{rs[k0 + 1][2]} read)")

# slip: tau = 0.3 s, u = 0.1 m/s
p = params("slip")
tau = p["slip_time_constant_s"]
rs = rows("slip")
k0 = onset(rs)
tof0 = rs[k0][4]
worst = 0
lags = []
end = next(k for k in range(k0 + 1, len(rs)) if rs[k][1] == 0)  # the first row commanding 0
for k in range(k0 + 1, end + 1):
    t = (k - k0) * TICK
    body = u * (t - tau * (1 - math.exp(-t / tau)))
    body_tof = (tof0 - rs[k][4]) / p["tof_scale"] / 1000
    worst = max(worst, abs(body_tof - body))
    wheel = rs[k][2] / spm
    if t >= 5 * tau:
        lags.append((wheel - body_tof) / u)
# 2 mm: the ToF reads whole mm (the first row's and this row's rounding, 1 mm) and ARGoS's
# dynamics2d moves the body by less than it is told on a tick where the speed changes (its
# velocity control is force-limited: 28 % short on a step from rest, about 1 mm over this ramp).
check(worst <= 0.002, f"slip: the ToF's body travel within {1000 * worst:.2f} mm of u (t - tau (1 - e^-t/tau)) "
      f"over {end - k0} moving rows")
tau_seen = sum(lags) / len(lags) if lags else float("nan")
check(lags and abs(tau_seen - tau) <= 0.05 * tau,
      f"slip: the ToF lags the encoders by {tau_seen:.3f} s once settled (file: tau = {tau} s; {len(lags)} rows)")

# still: noise 3 steps; while the command is 0 and the robot has stopped, readings do not change
rs = rows("still")
k0 = onset(rs)
first_still = all(r[2] == 0 and r[3] == 0 for r in rs[: k0 + 1])
check(first_still, f"still: {k0 + 1} rows standing still before the run read exactly 0 (encoder noise sd 3 steps)")
# after the stop: the wheels stop at once (no accel limit): every row from the second after the stop
stop = next(k for k in range(k0 + 1, len(rs)) if rs[k][1] == 0)
tail = rs[stop + 1:]
check(len(tail) >= 5 and all(r[2:4] == tail[0][2:4] for r in tail),
      f"still: {len(tail)} rows standing still after the run keep their count ({tail[0][2]}, {tail[0][3]}) exactly")
# and the noise is on while moving: readings differ from the noiseless floor(steps_per_m u t)
diffs = [rs[k][2] - math.floor(spm * u * (k - k0) * TICK) for k in range(k0 + 1, stop + 1)]
sd = (sum(d * d for d in diffs) / len(diffs)) ** 0.5
check(sd > 1.5, f"still: while moving the readings scatter {sd:.2f} steps about the noiseless count (noise on)")

sys.exit(1 if failures else 0)
