#!/usr/bin/env python3
"""The discharge rate of a silo run and Beverloo's law fitted to several (standard library only).

beverloo.py rate OUT/outlets.dat [--from T0] [--to T1]
    cdm's steady discharge rate: the least-squares slope of the mass removed (outlets.dat,
    its first outlet) against time over [T0, T1], in kg/s, with the slopes of the window's
    two halves (a steady flow gives the same three).
beverloo.py rate log.liggghts --liggghts --dt DT --mass M [--from T0] [--to T1]
    The same from LIGGGHTS's thermo output (step, atoms): the beads lost below the box,
    each of mass M.
beverloo.py fit D1:W1 D2:W2 D3:W3 --d D --density RHO_P --fraction PHI
    Beverloo's W = C rho_b sqrt(g) (D - k d)^(5/2) through three or more orifices D [m]
    and rates W [kg/s], rho_b = PHI rho_p: W^(2/5) is linear in D, so a straight line
    through (D, W^(2/5)) gives k d (where it crosses zero) and C (from its slope).
"""
import argparse
import math
import sys


def slope(ts, ms):
    n = len(ts)
    mt, mm = sum(ts) / n, sum(ms) / n
    stt = sum((t - mt) ** 2 for t in ts)
    return sum((t - mt) * (m - mm) for t, m in zip(ts, ms)) / stt


def series_cdm(path):
    ts, ms = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            c = line.split()
            ts.append(float(c[0]))
            ms.append(float(c[4]))  # the first outlet's mass removed since the start
    return ts, ms


def series_liggghts(path, dt, mass):
    ts, ms = [], []
    n0 = None
    with open(path) as f:
        header = False
        for line in f:
            c = line.split()
            if c[:2] == ["Step", "Atoms"]:
                header = True
                continue
            if header:
                try:
                    step, atoms = int(c[0]), int(c[1])
                except (ValueError, IndexError):
                    header = False
                    continue
                if n0 is None:
                    n0 = atoms
                ts.append(step * dt)
                ms.append((n0 - atoms) * mass)
    return ts, ms


def rate(ts, ms, t0, t1):
    sel = [(t, m) for t, m in zip(ts, ms) if t0 - 1e-9 <= t <= t1 + 1e-9]
    if len(sel) < 6:
        sys.exit("beverloo.py: fewer than 6 samples in [%g, %g] s" % (t0, t1))
    h = len(sel) // 2
    whole = slope(*zip(*sel))
    first = slope(*zip(*sel[: h + 1]))
    second = slope(*zip(*sel[h:]))
    return whole, first, second, sel[-1][1] - sel[0][1]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", choices=["rate", "fit"])
    ap.add_argument("args", nargs="+")
    ap.add_argument("--from", dest="t0", type=float, default=0.3)
    ap.add_argument("--to", dest="t1", type=float, default=math.inf)
    ap.add_argument("--liggghts", action="store_true")
    ap.add_argument("--dt", type=float)
    ap.add_argument("--mass", type=float)
    ap.add_argument("--d", type=float, default=0.004)
    ap.add_argument("--density", type=float, default=2500.0)
    ap.add_argument("--fraction", type=float, default=0.6)
    ap.add_argument("--g", type=float, default=9.81)
    a = ap.parse_args()
    if a.what == "rate":
        ts, ms = series_liggghts(a.args[0], a.dt, a.mass) if a.liggghts else series_cdm(a.args[0])
        w, w1, w2, m = rate(ts, ms, a.t0, min(a.t1, ts[-1]))
        print("W = %.5g kg/s (halves %.5g, %.5g; %.4g kg discharged over [%g, %g] s)" % (w, w1, w2, m, a.t0, min(a.t1, ts[-1])))
        return
    pts = [tuple(float(x) for x in s.split(":")) for s in a.args]
    ds = [p[0] for p in pts]
    ys = [p[1] ** 0.4 for p in pts]
    s = slope(ds, ys)
    i = sum(ys) / len(ys) - s * sum(ds) / len(ds)
    kd = -i / s
    rho_b = a.fraction * a.density
    c = s ** 2.5 / (rho_b * math.sqrt(a.g))
    print("C = %.4f, k = %.3f (rho_b = %g kg/m^3, d = %g m); residuals of W:" % (c, kd / a.d, rho_b, a.d))
    for d, w in pts:
        wf = c * rho_b * math.sqrt(a.g) * max(d - kd, 0.0) ** 2.5
        print("  D = %.4g m (%.3g d): W = %.5g kg/s, fit %.5g (%+.2f %%)" % (d, d / a.d, w, wf, 100 * (wf / w - 1)))


if __name__ == "__main__":
    main()
