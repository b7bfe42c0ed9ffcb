#!/usr/bin/env python3
"""Dynamic angle of repose of a rotating drum bed: the slope of its free surface.

For each snapshot after --from seconds, the bead centres are projected on the plane
normal to the drum axis (x, z for an axis along y) and cut into vertical columns of
width --bin (default 2 d). The surface height of a column is the mean of its three
highest centres (robust to a bead bouncing above the surface). A straight line is fitted
(least squares) to the columns in the middle 60 % of the bed's width, away from the
drum wall where the surface bends; the angle is atan|slope|. Prints the mean and the
standard deviation over the snapshots.

Reads cdm's particles.dat (columns t id x y z ...) or a LIGGGHTS dump (`dump custom N
file id x y z`, times from --dt). Snapshots before --to seconds only, if given.
"""
import argparse
import math
import sys


def cdm_snapshots(path):
    t_cur, pts = None, []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                continue
            c = line.split()
            if len(c) < 5:  # a row cut short (a run still writing)
                break
            t = float(c[0])
            if t_cur is not None and t != t_cur:
                yield t_cur, pts
                pts = []
            t_cur = t
            pts.append((float(c[2]), float(c[3]), float(c[4])))
    if pts:
        yield t_cur, pts  # (the last may be incomplete while a run is writing)


def liggghts_snapshots(path, dt):
    try:
        yield from _liggghts_snapshots(path, dt)
    except (StopIteration, IndexError, ValueError):  # a snapshot cut short (a run still writing)
        return


def _liggghts_snapshots(path, dt):
    with open(path) as f:
        lines = iter(f)
        for line in lines:
            if not line.startswith("ITEM: TIMESTEP"):
                continue
            step = int(next(lines))
            next(lines)
            n = int(next(lines))
            next(lines)
            for _ in range(3):
                next(lines)
            header = next(lines).split()[2:]
            ix, iy, iz = header.index("x"), header.index("y"), header.index("z")
            pts = []
            for _ in range(n):
                c = next(lines).split()
                pts.append((float(c[ix]), float(c[iy]), float(c[iz])))
            yield step * dt, pts


def surface_angle(pts, bin_width):
    """The free surface's angle [deg] and slope in the x-z plane, or None."""
    cols = {}
    for x, _, z in pts:
        cols.setdefault(math.floor(x / bin_width), []).append(z)
    keys = sorted(k for k in cols if len(cols[k]) >= 3)
    if len(keys) < 5:
        return None
    lo, hi = keys[0], keys[-1]
    span = hi - lo
    xs, zs = [], []
    for k in keys:
        if lo + 0.2 * span <= k <= hi - 0.2 * span:
            top = sorted(cols[k])[-3:]
            xs.append((k + 0.5) * bin_width)
            zs.append(sum(top) / 3.0)
    n = len(xs)
    if n < 3:
        return None
    mx, mz = sum(xs) / n, sum(zs) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    sxz = sum((x - mx) * (z - mz) for x, z in zip(xs, zs))
    slope = sxz / sxx
    return math.degrees(math.atan(abs(slope))), slope


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("file", help="cdm particles.dat or a LIGGGHTS dump")
    ap.add_argument("--format", choices=["cdm", "liggghts"], default="cdm")
    ap.add_argument("--dt", type=float, default=0.0, help="LIGGGHTS time step [s] (dump times)")
    ap.add_argument("--from", dest="t0", type=float, default=1.5, help="first snapshot time used [s]")
    ap.add_argument("--to", dest="t1", type=float, default=float("inf"), help="last snapshot time used [s]")
    ap.add_argument("--bin", type=float, default=6e-3, help="column width [m] (2 d)")
    ap.add_argument("--series", action="store_true", help="print each snapshot's angle")
    a = ap.parse_args()
    snaps = cdm_snapshots(a.file) if a.format == "cdm" else liggghts_snapshots(a.file, a.dt)
    angles = []
    for t, pts in snaps:
        if t < a.t0 - 1e-9 or t > a.t1 + 1e-9:
            continue
        r = surface_angle(pts, a.bin)
        if r is None:
            continue
        if a.series:
            print(f"# t = {t:.4f} s  angle = {r[0]:.2f} deg  slope = {r[1]:+.4f}")
        angles.append(r[0])
    if not angles:
        sys.exit("no snapshot after --from with a bed to fit")
    m = sum(angles) / len(angles)
    sd = math.sqrt(sum((x - m) ** 2 for x in angles) / max(1, len(angles) - 1))
    print(f"angle {m:.2f} deg  sd {sd:.2f} deg  snapshots {len(angles)}")


if __name__ == "__main__":
    main()
