#!/usr/bin/python3
"""Side by side: epuck2-fit's fitting engine against scipy.optimize.curve_fit and lmfit.

Runs bench_fit_engine (C++, the project's engine) for its coefficients and wall times, fits the
same data with the same models from the same starting points with scipy and lmfit, and prints per
tool the wall time, its ratio to epuck2-fit, and the digits to which the coefficients agree with
ours (min over parameters of the log relative error of theirs against ours). Data:

  (a) the 27 NIST StRD problems from start 1 (tests/data/nist/*.dat);
  (b) the battery reference set: per speed, a cubic charge = a u^3 + b u^2 + c u + d in scaled
      time u = time_s / 3600 (the same scaling in every tool), on the pooled logs
      data/raw/battery/robot-X_speed-SS.csv, from (a, b, c, d) = (0, 0, 0, 1).

scipy and lmfit both use MINPACK's Levenberg-Marquardt (lmdif, forward-difference Jacobian) with
ftol = xtol = 1e-12 and maxfev = 20000; epuck2-fit uses Ceres with automatic derivatives. Each fit
is repeated until --min-seconds have passed (at least 5 times); medians are reported. The battery
set is timed in --rounds rounds (epuck2-fit, then scipy, then lmfit, on the whole set each round),
so that all three see the same machine load; per fit the median over rounds is reported, and the
lmfit/epuck2-fit ratio of every round.

Usage: /usr/bin/python3 bench/side_by_side.py [--engine build/bin/bench_fit_engine]
           [--nist tests/data/nist] [--battery data/raw/battery] [--min-seconds 0.2] [--rounds 3]
           [--default-heap] [--json OUT]
"""
import argparse
import csv
import glob
import json
import math
import os
import re
import statistics
import subprocess
import sys
import time
import warnings

import numpy as np
import scipy
import scipy.optimize
import lmfit

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOL = dict(ftol=1e-12, xtol=1e-12, maxfev=20000)
HOUR_S = 3600.0  # the battery cubic's time unit, as in bench/fit_engine_bench.cpp
MIN_REPEATS = 5
AGREEMENT_CAP = 15.0  # digits: two doubles cannot usefully agree to more
CERTIFIED_DIGITS = 11.0

# --- The NIST models: the "Model:" block of each .dat file (same formulas as lib/fit nist.hpp).
e = np.exp
PI = math.pi


def rational33(x, b1, b2, b3, b4, b5, b6, b7):
    return (b1 + b2 * x + b3 * x**2 + b4 * x**3) / (1 + b5 * x + b6 * x**2 + b7 * x**3)


def lanczos(x, b1, b2, b3, b4, b5, b6):
    return b1 * e(-b2 * x) + b3 * e(-b4 * x) + b5 * e(-b6 * x)


def gauss(x, b1, b2, b3, b4, b5, b6, b7, b8):
    return b1 * e(-b2 * x) + b3 * e(-(x - b4) ** 2 / b5**2) + b6 * e(-(x - b7) ** 2 / b8**2)


def misra1a(x, b1, b2):
    return b1 * (1 - e(-b2 * x))


def chwirut(x, b1, b2, b3):
    return e(-b1 * x) / (b2 + b3 * x)


MODELS = {
    "Misra1a": misra1a,
    "Chwirut2": chwirut,
    "Chwirut1": chwirut,
    "Lanczos3": lanczos,
    "Gauss1": gauss,
    "Gauss2": gauss,
    "DanWood": lambda x, b1, b2: b1 * x**b2,
    "Misra1b": lambda x, b1, b2: b1 * (1 - (1 + b2 * x / 2) ** (-2)),
    "Kirby2": lambda x, b1, b2, b3, b4, b5: (b1 + b2 * x + b3 * x**2) / (1 + b4 * x + b5 * x**2),
    "Hahn1": rational33,
    # Nelson: log y = b1 - b2*x1*exp(-b3*x2); x is the 2-row array (x1, x2), the response log y
    "Nelson": lambda x, b1, b2, b3: b1 - b2 * x[0] * e(-b3 * x[1]),
    "MGH17": lambda x, b1, b2, b3, b4, b5: b1 + b2 * e(-x * b4) + b3 * e(-x * b5),
    "Lanczos1": lanczos,
    "Lanczos2": lanczos,
    "Gauss3": gauss,
    "Misra1c": lambda x, b1, b2: b1 * (1 - (1 + 2 * b2 * x) ** (-0.5)),
    "Misra1d": lambda x, b1, b2: b1 * b2 * x * ((1 + b2 * x) ** (-1)),
    "Roszman1": lambda x, b1, b2, b3, b4: b1 - b2 * x - np.arctan(b3 / (x - b4)) / PI,
    "ENSO": lambda x, b1, b2, b3, b4, b5, b6, b7, b8, b9: (
        b1 + b2 * np.cos(2 * PI * x / 12) + b3 * np.sin(2 * PI * x / 12)
        + b5 * np.cos(2 * PI * x / b4) + b6 * np.sin(2 * PI * x / b4)
        + b8 * np.cos(2 * PI * x / b7) + b9 * np.sin(2 * PI * x / b7)),
    "MGH09": lambda x, b1, b2, b3, b4: b1 * (x**2 + x * b2) / (x**2 + x * b3 + b4),
    "Thurber": rational33,
    "BoxBOD": misra1a,
    "Rat42": lambda x, b1, b2, b3: b1 / (1 + e(b2 - b3 * x)),
    "MGH10": lambda x, b1, b2, b3: b1 * e(b2 / (x + b3)),
    "Eckerle4": lambda x, b1, b2, b3: (b1 / b2) * e(-0.5 * ((x - b3) / b2) ** 2),
    "Rat43": lambda x, b1, b2, b3, b4: b1 / ((1 + e(b2 - b3 * x)) ** (1 / b4)),
    "Bennett5": lambda x, b1, b2, b3: b1 * (b2 + x) ** (-1 / b3),
}


def cubic(u, a, b, c, d):
    return ((a * u + b) * u + c) * u + d


def read_dat(path):
    """Certified values and data of a StRD file (the same fields validation/nist/nist.cpp reads)."""
    params, rows, in_data = [], [], False
    for line in open(path, encoding="ascii"):
        t = line.split()
        if not t:
            continue
        if in_data:
            rows.append([float(v) for v in t])
        elif re.fullmatch(r"b\d+", t[0]) and len(t) == 6 and t[1] == "=":
            params.append(dict(name=t[0], start1=float(t[2]), certified=float(t[4])))
        elif t[0] == "Data:" and len(t) >= 3 and t[1] == "y":
            in_data = True
    a = np.array(rows)
    y = a[:, 0]
    x = a[:, 1] if a.shape[1] == 2 else a[:, 1:].T
    return params, x, y


def read_battery(folder):
    """Pooled (u, charge) per speed from robot-X_speed-SS.csv."""
    sets = {}
    for path in sorted(glob.glob(os.path.join(folder, "robot-*_speed-*.csv"))):
        m = re.fullmatch(r"robot-([A-Za-z0-9]+)_speed-([0-9]+)\.csv", os.path.basename(path))
        if not m:
            continue
        lines = [l for l in open(path, encoding="utf-8") if not l.startswith("#") and l.strip()]
        reader = csv.DictReader(lines)
        u, q = [], []
        for row in reader:
            u.append(float(row["time_s"]) / HOUR_S)
            q.append(float(row["charge"]))
        s = sets.setdefault(int(m.group(2)), ([], []))
        s[0].extend(u)
        s[1].extend(q)
    return {k: (np.array(v[0]), np.array(v[1])) for k, v in sorted(sets.items())}


def lre(x, ref, cap):
    if x is None or ref is None or not math.isfinite(x):
        return 0.0
    if x == ref:
        return cap
    rel = abs(x - ref) / abs(ref) if ref != 0 else abs(x - ref)
    return max(0.0, min(cap, -math.log10(rel)))


def min_lre(values, refs, cap):
    if values is None:
        return 0.0
    return min(lre(v, r, cap) for v, r in zip(values, refs))


def median_time(fn, min_seconds):
    times, begin = [], time.perf_counter()
    while len(times) < MIN_REPEATS or time.perf_counter() - begin < min_seconds:
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def fit_scipy(f, x, y, p0):
    try:
        p, _ = scipy.optimize.curve_fit(f, x, y, p0=p0, method="lm", **TOL)
        return [float(v) for v in p] if np.all(np.isfinite(p)) else None
    except (RuntimeError, ValueError, OverflowError, scipy.optimize.OptimizeWarning):
        return None


def fit_lmfit(f, x, y, p0):
    names = ["p%d" % i for i in range(len(p0))]
    params = lmfit.Parameters()
    for n, v in zip(names, p0):
        params.add(n, value=v)

    def residual(ps):
        return y - f(x, *[ps[n].value for n in names])

    try:
        out = lmfit.minimize(residual, params, method="leastsq", **TOL)
        vals = [float(out.params[n].value) for n in names]
        return vals if all(math.isfinite(v) for v in vals) else None
    except (RuntimeError, ValueError, OverflowError):
        return None


def compare(f, x, y, p0, ours, min_seconds):
    row = {}
    for tool, fitter in (("scipy", fit_scipy), ("lmfit", fit_lmfit)):
        vals = fitter(f, x, y, p0)
        t = median_time(lambda: fitter(f, x, y, p0), min_seconds)
        row[tool] = dict(values=vals, seconds=t, agreement=min_lre(vals, ours, AGREEMENT_CAP))
    return row


def machine():
    cpu, cores = "unknown", 0
    try:
        for line in open("/proc/cpuinfo", encoding="ascii", errors="replace"):
            if line.startswith("model name") and cpu == "unknown":
                cpu = line.split(":", 1)[1].strip()
            if line.startswith("processor"):
                cores += 1
    except OSError:
        pass
    return dict(cpu=cpu, logical_cores=cores or os.cpu_count(), python=sys.version.split()[0],
                numpy=np.__version__, scipy=scipy.__version__, lmfit=lmfit.__version__)


def find_engine():
    for p in sorted(glob.glob(os.path.join(REPO, "build*", "bin", "bench_fit_engine"))):
        return p
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--engine", default=find_engine(), help="path to bench_fit_engine")
    ap.add_argument("--nist", default=os.path.join(REPO, "tests", "data", "nist"))
    ap.add_argument("--battery", default=os.path.join(REPO, "data", "raw", "battery"))
    ap.add_argument("--min-seconds", type=float, default=0.2, help="minimum time spent repeating each fit")
    ap.add_argument("--rounds", type=int, default=3,
                    help="battery set: rounds of (epuck2-fit, scipy, lmfit) timings, one after the other; "
                         "medians over rounds are reported")
    ap.add_argument("--default-heap", action="store_true",
                    help="run bench_fit_engine with glibc's default heap trimming (its --default-heap)")
    ap.add_argument("--json", help="also write the full comparison here")
    a = ap.parse_args()
    if not a.engine or not os.path.exists(a.engine):
        sys.exit("bench_fit_engine not found: build it (cmake --build BUILD --target bench_fit_engine) or pass --engine")
    warnings.simplefilter("ignore")  # overflow in trial steps, covariance warnings: the results say
    np.seterr(all="ignore")

    def engine(*args):
        heap = ["--default-heap"] if a.default_heap else []
        return json.loads(subprocess.run([a.engine, *args, *heap, "--min-seconds", str(a.min_seconds)],
                                         check=True, capture_output=True, text=True).stdout)

    ours = engine("--nist", a.nist)
    m = machine()
    print("machine: %s, %s logical cores; Python %s, numpy %s, scipy %s, lmfit %s; epuck2-fit heap: %s" % (
        m["cpu"], m["logical_cores"], m["python"], m["numpy"], m["scipy"], m["lmfit"], ours.get("heap")))
    report = dict(machine=m, engine_machine=ours["machine"], engine_heap=ours.get("heap"), tolerances=TOL,
                  nist=[], battery=[])

    print("\n(a) NIST StRD, start 1. LRE vs certified (cap 11); 'agree' = digits in common with epuck2-fit (cap 15)")
    hdr = "%-9s %8s %8s | %8s %7s %6s %6s | %8s %7s %6s %6s"
    print(hdr % ("problem", "ours ms", "LRE", "scipy ms", "ratio", "LRE", "agree", "lmfit ms", "ratio", "LRE", "agree"))
    totals = dict(ours=0.0, ours_single=0.0, scipy=0.0, lmfit=0.0)
    for run in ours["nist"]:
        name = run["problem"]
        params, x, y = read_dat(os.path.join(a.nist, name + ".dat"))
        if name == "Nelson":
            y = np.log(y)
        cert = [p["certified"] for p in params]
        p0 = [p["start1"] for p in params]
        row = compare(MODELS[name], x, y, p0, run["values"], a.min_seconds)
        our_lre = min_lre(run["values"], cert, CERTIFIED_DIGITS)
        for tool in ("scipy", "lmfit"):
            row[tool]["certified_lre"] = min_lre(row[tool]["values"], cert, CERTIFIED_DIGITS)
            row[tool]["ratio"] = row[tool]["seconds"] / run["seconds"]
            totals[tool] += row[tool]["seconds"]
        totals["ours"] += run["seconds"]
        totals["ours_single"] += run["seconds_single_solve"]
        print("%-9s %8.3f %8.2f | %8.3f %7.2f %6.2f %6.2f | %8.3f %7.2f %6.2f %6.2f" % (
            name, run["seconds"] * 1e3, our_lre,
            row["scipy"]["seconds"] * 1e3, row["scipy"]["ratio"], row["scipy"]["certified_lre"], row["scipy"]["agreement"],
            row["lmfit"]["seconds"] * 1e3, row["lmfit"]["ratio"], row["lmfit"]["certified_lre"], row["lmfit"]["agreement"]))
        report["nist"].append(dict(problem=name, ours=dict(values=run["values"], seconds=run["seconds"],
                                                           seconds_single_solve=run["seconds_single_solve"],
                                                           certified_lre=our_lre), **row))
    n_ok = {t: sum(1 for r in report["nist"] if r[t]["certified_lre"] >= 6) for t in ("scipy", "lmfit")}
    n_ok["ours"] = sum(1 for r in report["nist"] if r["ours"]["certified_lre"] >= 6)
    print("NIST totals: epuck2-fit %.1f ms (one plain LM solve each: %.1f ms), scipy %.1f ms (%.2fx ours), lmfit %.1f ms (%.2fx ours)" % (
        totals["ours"] * 1e3, totals["ours_single"] * 1e3, totals["scipy"] * 1e3, totals["scipy"] / totals["ours"],
        totals["lmfit"] * 1e3, totals["lmfit"] / totals["ours"]))
    print("NIST start 1 with parameter LRE >= 6: epuck2-fit %d/27, scipy %d/27, lmfit %d/27" % (
        n_ok["ours"], n_ok["scipy"], n_ok["lmfit"]))
    report["nist_totals"] = dict(seconds=totals, at_lre6=n_ok)

    print("\n(b) Battery reference set: cubic in u = time_s/3600 per speed, pooled logs, start (0,0,0,1)")
    print("%d rounds, each: bench_fit_engine on the whole set, then scipy, then lmfit on it; per fit the median"
          " over repeats, then per tool the median over rounds (the same machine load for all three)" % a.rounds)
    data = read_battery(a.battery)
    rounds = []  # per round: the engine's sets and, per speed, the Python tools' rows
    for k in range(a.rounds):
        engine_sets = engine("--battery", a.battery)["battery"]["sets"]
        rows = {}
        for s in engine_sets:
            u, q = data[s["speed_cm_s"]]
            if len(u) != s["observations"]:
                sys.exit("battery speed %d: %d rows here, %d in the engine" % (s["speed_cm_s"], len(u), s["observations"]))
            rows[s["speed_cm_s"]] = compare(cubic, u, q, [0.0, 0.0, 0.0, 1.0], s["values"], a.min_seconds)
        total = dict(ours=sum(s["seconds"] for s in engine_sets),
                     scipy=sum(r["scipy"]["seconds"] for r in rows.values()),
                     lmfit=sum(r["lmfit"]["seconds"] for r in rows.values()))
        print("round %d: epuck2-fit %.2f ms, scipy %.2f ms (%.2fx ours), lmfit %.2f ms (%.2fx ours)" % (
            k + 1, total["ours"] * 1e3, total["scipy"] * 1e3, total["scipy"] / total["ours"], total["lmfit"] * 1e3,
            total["lmfit"] / total["ours"]))
        rounds.append(dict(sets=engine_sets, rows=rows, totals=total))

    def med(values):
        return statistics.median(values)

    print("%6s %6s %8s | %8s %7s %6s | %8s %7s %6s" % ("speed", "n", "ours ms", "scipy ms", "ratio", "agree",
                                                    "lmfit ms", "ratio", "agree"))
    bt = dict(ours=0.0, scipy=0.0, lmfit=0.0)
    variant_seconds, variant_agree = {}, {}
    agree = dict(scipy=AGREEMENT_CAP, lmfit=AGREEMENT_CAP)
    for i, s in enumerate(rounds[0]["sets"]):
        speed = s["speed_cm_s"]
        u, _ = data[speed]
        ours_t = med([r["sets"][i]["seconds"] for r in rounds])
        bt["ours"] += ours_t
        row = {}
        for tool in ("scipy", "lmfit"):
            t = med([r["rows"][speed][tool]["seconds"] for r in rounds])
            # Agreement with our coefficients: the worst over rounds (every round refits).
            ag = min(min_lre(r["rows"][speed][tool]["values"], r["sets"][i]["values"], AGREEMENT_CAP) for r in rounds)
            row[tool] = dict(values=rounds[0]["rows"][speed][tool]["values"], seconds=t, ratio=t / ours_t, agreement=ag)
            bt[tool] += t
            agree[tool] = min(agree[tool], ag)
        for key in s.get("variants", {}):
            vt = med([r["sets"][i]["variants"][key]["seconds"] for r in rounds])
            variant_seconds[key] = variant_seconds.get(key, 0.0) + vt
            variant_agree[key] = min(variant_agree.get(key, AGREEMENT_CAP),
                                     min_lre(s["variants"][key]["values"], s["values"], AGREEMENT_CAP))
        print("%6d %6d %8.3f | %8.3f %7.2f %6.2f | %8.3f %7.2f %6.2f" % (
            speed, len(u), ours_t * 1e3, row["scipy"]["seconds"] * 1e3, row["scipy"]["ratio"],
            row["scipy"]["agreement"], row["lmfit"]["seconds"] * 1e3, row["lmfit"]["ratio"], row["lmfit"]["agreement"]))
        report["battery"].append(dict(speed_cm_s=speed, observations=len(u),
                                      ours=dict(values=s["values"], seconds=ours_t), **row))
    if bt["ours"] > 0:
        round_ratios = [r["totals"]["lmfit"] / r["totals"]["ours"] for r in rounds]
        print("Battery totals (per-fit medians over rounds): epuck2-fit %.2f ms, scipy %.2f ms (%.2fx ours),"
              " lmfit %.2f ms (%.2fx ours)" % (bt["ours"] * 1e3, bt["scipy"] * 1e3, bt["scipy"] / bt["ours"],
                                               bt["lmfit"] * 1e3, bt["lmfit"] / bt["ours"]))
        print("lmfit / epuck2-fit per round: %s (lowest %.2fx)" % (
            ", ".join("%.2fx" % v for v in round_ratios), min(round_ratios)))
        print("Battery agreement with epuck2-fit (min over speeds, coefficients and rounds): scipy %.2f digits,"
              " lmfit %.2f digits" % (agree["scipy"], agree["lmfit"]))
        for key in sorted(variant_seconds):
            print("epuck2-fit variant %s: %.2f ms (scipy %.2fx, lmfit %.2fx of it), agrees with the default to %.2f digits" % (
                key, variant_seconds[key] * 1e3, bt["scipy"] / variant_seconds[key], bt["lmfit"] / variant_seconds[key],
                variant_agree[key]))
        target_speed = bt["lmfit"] / bt["ours"] >= 10 and min(round_ratios) >= 10
        target_digits = min(agree.values()) >= 6
        print("Targets: >= 10x faster than lmfit on the battery set (the medians and every round): %s (%.1fx, lowest"
              " round %.1fx); coefficients agree to 6 digits: %s" % (
                  "met" if target_speed else "NOT met", bt["lmfit"] / bt["ours"], min(round_ratios),
                  "met" if target_digits else "NOT met"))
        report["battery_totals"] = dict(seconds=bt, agreement=agree, lmfit_ratio=bt["lmfit"] / bt["ours"],
                                        scipy_ratio=bt["scipy"] / bt["ours"], lmfit_ratio_per_round=round_ratios,
                                        round_totals=[r["totals"] for r in rounds],
                                        variant_seconds=variant_seconds, variant_agreement=variant_agree)
    if a.json:
        tmp = a.json + ".tmp"
        with open(tmp, "w", encoding="utf-8") as fh:
            json.dump(report, fh, indent=2)
            fh.write("\n")
        os.replace(tmp, a.json)


if __name__ == "__main__":
    main()
