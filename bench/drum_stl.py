#!/usr/bin/env python3
"""The rotating-drum comparison's LIGGGHTS inputs (bench/drum_compare.sh).

drum_stl.py OUT.stl --radius R --length W --segments N
    A closed cylinder about the y axis from y = 0 to y = W, as an ASCII STL: the lateral
    surface as N flat facets whose mid-lines lie at radius R (vertices at R / cos(pi/N)),
    so a bead touches a facet where it would touch cdm's analytic cylinder, and each end
    a fan of N triangles. Normals point into the drum.
drum_stl.py --data particles.dat OUT.data [--box XLO XHI YLO YHI ZLO ZHI] [--time T] [--density RHO]
    cdm's particles of the table's first sample (or of its sample at T) as a LIGGGHTS data
    file (atom_style granular: id type diameter density x y z, and the velocities and
    spins), which LAMMPS's atom_style sphere reads alike; the type cdm's material index +
    1 (density RHO, 2500 kg/m^3 unless given; the drum's and the silo's beads are type 1,
    their mesh type 2); the box is the drum's unless given (the silo comparison,
    bench/silo_compare.sh, and the Müller bed's, bench/mueller_dem_compare.sh, give their own).
"""
import argparse
import math


def write_stl(path, radius, length, n):
    rv = radius / math.cos(math.pi / n)
    ring = [(rv * math.cos(2 * math.pi * k / n), rv * math.sin(2 * math.pi * k / n)) for k in range(n)]
    tris = []
    for k in range(n):
        (x0, z0), (x1, z1) = ring[k], ring[(k + 1) % n]
        a, b, c, d = (x0, 0.0, z0), (x1, 0.0, z1), (x1, length, z1), (x0, length, z0)
        tris += [(a, b, c), (a, c, d)]
        tris.append(((0.0, 0.0, 0.0), (x1, 0.0, z1), (x0, 0.0, z0)))
        tris.append(((0.0, length, 0.0), (x0, length, z0), (x1, length, z1)))
    with open(path, "w") as f:
        f.write("solid drum\n")
        for p, q, r in tris:
            u = [q[i] - p[i] for i in range(3)]
            v = [r[i] - p[i] for i in range(3)]
            nrm = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
            s = math.sqrt(sum(c * c for c in nrm))
            f.write("  facet normal %.9e %.9e %.9e\n    outer loop\n" % tuple(c / s for c in nrm))
            for vert in (p, q, r):
                f.write("      vertex %.12e %.12e %.12e\n" % vert)
            f.write("    endloop\n  endfacet\n")
        f.write("endsolid drum\n")


DRUM_BOX = (-0.06, 0.06, -0.002, 0.02, -0.06, 0.06)


def write_data(particles, path, density=2500.0, box=DRUM_BOX, time=None):
    rows = []
    t0 = None
    with open(particles) as f:
        for line in f:
            if line.startswith("#"):
                continue
            c = line.split()
            if time is not None and abs(float(c[0]) - time) > 1e-9 * max(1.0, abs(time)):
                if rows:
                    break
                continue
            if t0 is None:
                t0 = c[0]
            if c[0] != t0:
                break
            # atom type: the cdm material's index + 1 (the last column)
            w = [float(x) for x in c[8:11]] if len(c) == 13 else [0.0, 0.0, 0.0]  # spin, with rotation
            rows.append((int(c[1]) + 1, int(c[-1]) + 1, float(c[2]), float(c[3]), float(c[4]), 2.0 * float(c[-2]),
                         [float(x) for x in c[5:8]] + w))
    if not rows:
        raise SystemExit("drum_stl.py: %s has no sample%s" % (particles, "" if time is None else " at t = %g s" % time))
    with open(path, "w") as f:
        f.write("LIGGGHTS data file: cdm's beads at t = %s s\n\n%d atoms\n2 atom types\n\n" % (t0, len(rows)))
        f.write("%.17g %.17g xlo xhi\n%.17g %.17g ylo yhi\n%.17g %.17g zlo zhi\n\nAtoms\n\n" % tuple(box))
        for i, ty, x, y, z, d, _ in rows:
            f.write("%d %d %.17g %.17g %.17g %.17g %.17g\n" % (i, ty, d, density, x, y, z))
        f.write("\nVelocities\n\n")
        for r in rows:
            f.write("%d %.17g %.17g %.17g %.17g %.17g %.17g\n" % (r[0], *r[6]))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--radius", type=float, default=0.05)
    ap.add_argument("--length", type=float, default=0.018)
    ap.add_argument("--segments", type=int, default=120)
    ap.add_argument("--data", help="cdm particles.dat: write its first sample's beads as a LIGGGHTS data file")
    ap.add_argument("--time", type=float, help="with --data: the sample at this time [s] instead of the first")
    ap.add_argument("--density", type=float, default=2500.0, help="with --data: the beads' density [kg/m^3]")
    ap.add_argument("--box", type=float, nargs=6, default=DRUM_BOX, help="the data file's box: xlo xhi ylo yhi zlo zhi")
    a = ap.parse_args()
    if a.data:
        write_data(a.data, a.out, density=a.density, box=a.box, time=a.time)
    else:
        write_stl(a.out, a.radius, a.length, a.segments)


if __name__ == "__main__":
    main()
