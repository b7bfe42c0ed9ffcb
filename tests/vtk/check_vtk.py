#!/usr/bin/python3
"""Reads cdm's VTK output back with VTK's own readers (Debian python3-vtk9) and checks
it against cdm's particle table and against the Taylor-Green field computed here from
its formula: counts, times, positions, velocities, grid geometry and cell values."""
import math
import re
import sys

import vtk
from vtk.util.numpy_support import vtk_to_numpy

out = sys.argv[1]
fails = []


def check(cond, what):
    if not cond:
        fails.append(what)


# The particle table: t id x y z vx vy vz radius material, one row per particle per sample.
rows = [list(map(float, l.split())) for l in open(f"{out}/particles.dat") if not l.startswith("#")]
times = sorted({r[0] for r in rows})

coll = open(f"{out}/particles.pvd").read()
entries = re.findall(r'timestep="([^"]+)" part="0" file="([^"]+)"', coll)
check(len(entries) == len(times), f"particles.pvd lists {len(entries)} files, the table has {len(times)} samples")
for (ts, fname), t in zip(entries, times):
    check(abs(float(ts) - t) <= 1e-15 * max(1.0, t), f"{fname}: time {ts} vs table {t}")
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(f"{out}/{fname}")
    r.Update()
    pd = r.GetOutput()
    table = [row for row in rows if row[0] == t]
    check(pd.GetNumberOfPoints() == len(table), f"{fname}: {pd.GetNumberOfPoints()} points, table {len(table)}")
    check(pd.GetNumberOfVerts() == len(table), f"{fname}: {pd.GetNumberOfVerts()} vertices")
    pts = vtk_to_numpy(pd.GetPoints().GetData())
    vel = vtk_to_numpy(pd.GetPointData().GetArray("velocity"))
    ids = vtk_to_numpy(pd.GetPointData().GetArray("id"))
    rad = vtk_to_numpy(pd.GetPointData().GetArray("radius"))
    tfile = vtk_to_numpy(pd.GetFieldData().GetArray("TIME"))[0]
    check(abs(tfile - t) <= 1e-15 * max(1.0, t), f"{fname}: TIME {tfile} vs {t}")
    mat = vtk_to_numpy(pd.GetPointData().GetArray("material"))
    names = pd.GetFieldData().GetAbstractArray("material_names")
    check(names is not None and names.GetNumberOfValues() == 1 and names.GetValue(0) == "glass",
          f"{fname}: material_names")
    check(pd.GetPointData().GetArray("contact_force") is None, f"{fname}: contact_force without contacts")
    for k, row in enumerate(table):
        check(int(ids[k]) == int(row[1]), f"{fname}: id {ids[k]} vs {row[1]}")
        for c in range(3):
            check(abs(pts[k][c] - row[2 + c]) <= 1e-15 * abs(row[2 + c]) + 1e-300, f"{fname}: particle {k} position")
            check(abs(vel[k][c] - row[5 + c]) <= 1e-15 * abs(row[5 + c]) + 1e-300, f"{fname}: particle {k} velocity")
        check(rad[k] == 5.0e-5 and rad[k] == row[8], f"{fname}: radius {rad[k]}")
        check(mat[k] == row[9] == 0, f"{fname}: material {mat[k]} vs {row[9]}")

# The gas: 8 x 12 cells on [0, 0.01] x [0, 0.02], depth 1e-4; u on x-faces, v on y-faces.
U, kx, ky, rho = 0.05, 628.3185307179587, 314.1592653589793, 1.2
nx, ny, lx, ly = 8, 12, 0.01, 0.02
hx, hy = lx / nx, ly / ny
gcoll = open(f"{out}/gas.pvd").read()
gentries = re.findall(r'timestep="([^"]+)" part="0" file="([^"]+)"', gcoll)
check(len(gentries) == len(times), f"gas.pvd lists {len(gentries)} files")
for (ts, fname), t in zip(gentries, times):
    r = vtk.vtkXMLImageDataReader()
    r.SetFileName(f"{out}/{fname}")
    r.Update()
    img = r.GetOutput()
    check(img.GetNumberOfCells() == nx * ny, f"{fname}: {img.GetNumberOfCells()} cells")
    check(tuple(img.GetDimensions()) == (nx + 1, ny + 1, 2), f"{fname}: dimensions {img.GetDimensions()}")
    sp = img.GetSpacing()
    check(abs(sp[0] - hx) < 1e-18 and abs(sp[1] - hy) < 1e-18 and abs(sp[2] - 1e-4) < 1e-18, f"{fname}: spacing {sp}")
    vel = vtk_to_numpy(img.GetCellData().GetArray("velocity"))
    pres = vtk_to_numpy(img.GetCellData().GetArray("pressure"))
    # Solids velocity: the particles (all of one radius) binned by centre, mean per cell.
    # cdm sums each cell exactly on a unit of 2^-62 of the largest sum the N particles
    # could reach (N r^3 max|v|, rounded up to a power of two: exact_sums.hpp), each
    # term rounded by less than one unit; the weights are summed alike. A cell's mean is
    # then within N 2^-60 max|v| of the exact one (this file's N is about 100: ~1e-16 of
    # max|v|), and this double sum within 1e-15 of it.
    solids = vtk_to_numpy(img.GetCellData().GetArray("solids_velocity"))
    want = {}
    now = [r for r in rows if r[0] == t]
    vmax = max((abs(x) for r in now for x in r[5:8]), default=0.0)
    for row in now:
        c = int(math.floor(row[2] / hx)) % nx + nx * (int(math.floor(row[3] / hy)) % ny)
        want.setdefault(c, []).append(row[5:8])
    for c in range(nx * ny):
        vs = want.get(c, [[0.0, 0.0, 0.0]])
        mean = [sum(v[a] for v in vs) / len(vs) for a in range(3)]
        tol = [1e-15 * abs(mean[a]) + len(now) * 2.0**-60 * vmax + 1e-300 for a in range(3)]
        check(all(abs(solids[c][a] - mean[a]) <= tol[a] for a in range(3)),
              f"{fname}: cell {c} solids_velocity {solids[c]} vs {mean}")
    for j in range(ny):
        for i in range(nx):
            c = i + nx * j
            yc, xc = (j + 0.5) * hy, (i + 0.5) * hx
            # Cell value = mean of the two face samples of u = -U cos(kx x) sin(ky y) (and v).
            ue = 0.5 * (-U * math.cos(kx * i * hx) * math.sin(ky * yc) - U * math.cos(kx * (i + 1) * hx) * math.sin(ky * yc))
            ve = 0.5 * (U * math.sin(kx * xc) * math.cos(ky * j * hy) + U * math.sin(kx * xc) * math.cos(ky * (j + 1) * hy))
            pe = -0.25 * rho * U * U * (math.cos(2 * kx * xc) + math.cos(2 * ky * yc))
            check(abs(vel[c][0] - ue) < 1e-14 and abs(vel[c][1] - ve) < 1e-14 and vel[c][2] == 0.0,
                  f"{fname}: cell ({i},{j}) velocity {vel[c]} vs ({ue}, {ve}, 0)")
            check(abs(pres[c] - pe) < 1e-14, f"{fname}: cell ({i},{j}) pressure {pres[c]} vs {pe}")

if fails:
    print(f"check_vtk: {len(fails)} failure(s):")
    for f in fails[:20]:
        print("  " + f)
    sys.exit(1)
print(f"check_vtk: {len(entries)} particle files and {len(gentries)} gas files read back with VTK "
      f"{vtk.vtkVersion.GetVTKVersion()}: counts, times, positions, velocities and cell values agree")
