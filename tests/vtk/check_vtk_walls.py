#!/usr/bin/python3
"""Reads back the wall frames (walls.pvd) that VTK's readers see and checks every point
against where the scene's motion puts each surface at the frame's TIME:
  MOVING: tests/cli/scenes/moving_walls.toml: an oscillating floor, a descending piston, a
  capped cylinder orbiting the box's axis at 40 rad/s, a cone turning at -15 rad/s about
  its own axis, four planes at rest: one wall frame per particle frame;
  MESH: tests/cli/scenes/mesh_pile.toml with its cube mesh (half-width 1.5 cm) turning at
  OMEGA rad/s about z through the origin: every vertex on the turned cube's surface;
  STATIC: a bed in a box of planes at rest: one wall frame only.
Usage: check_vtk_walls.py MOVING MESH OMEGA STATIC"""
import math
import re
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

moving, mesh, omega, static = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
fails = []


def check(cond, what):
    if not cond:
        fails.append(what)


def frames(out):
    """(time, polydata) of every frame walls.pvd lists."""
    out_frames = []
    for m in re.finditer(r'<DataSet timestep="([^"]+)" part="0" file="([^"]+)"/>', open(f"{out}/walls.pvd").read()):
        rd = vtk.vtkXMLPolyDataReader()
        rd.SetFileName(f"{out}/{m.group(2)}")
        rd.Update()
        out_frames.append((float(m.group(1)), rd.GetOutput()))
    return out_frames


def pvd_count(out, name):
    return open(f"{out}/{name}.pvd").read().count("<DataSet")


def cells(poly):
    """Per polygon: the wall index and the point ids."""
    wall = vtk_to_numpy(poly.GetCellData().GetArray("wall"))
    ids = []
    for c in range(poly.GetNumberOfCells()):
        cell = poly.GetCell(c)
        ids.append([cell.GetPointId(k) for k in range(cell.GetNumberOfPoints())])
    return wall, ids


def names(poly):
    a = poly.GetFieldData().GetAbstractArray("wall_names")
    return [a.GetValue(k) for k in range(a.GetNumberOfValues())]


def time_of(poly):
    return vtk_to_numpy(poly.GetFieldData().GetArray("TIME"))[0]


# Moving walls: one frame per particle frame, each surface where its motion has it.
fr = frames(moving)
check(len(fr) == pvd_count(moving, "particles") > 1, f"moving: {len(fr)} wall frames for {pvd_count(moving, 'particles')} particle frames")
o = np.array([0.011, 0.011])
seen = set()
for t, poly in fr:
    check(abs(time_of(poly) - t) <= 1e-15 * max(1.0, t), f"moving: TIME {time_of(poly)} is not the collection's {t}")
    check(names(poly) == ["floor", "piston", "stirrer", "stirrer.end_cap", "funnel", "x-", "x+", "y-", "y+"], f"moving: wall_names {names(poly)}")
    x = vtk_to_numpy(poly.GetPoints().GetData())
    wall, ids = cells(poly)
    for w in range(9):
        pts = x[sorted({i for c, l in zip(wall, ids) if c == w for i in l})]
        check(len(pts) > 0, f"moving t={t}: wall {w} has no polygon")
        if len(pts) == 0:
            continue
        seen.add(w)
        if w == 0:
            check(np.allclose(pts[:, 2], 0.0003 * math.sin(2 * math.pi * 50.0 * t), rtol=0, atol=1e-15), f"moving t={t}: the floor is not where it oscillates to")
        elif w == 1:
            check(np.allclose(pts[:, 2], 0.03 - 0.5 * t, rtol=0, atol=1e-15), f"moving t={t}: the piston is not at 0.03 - 0.5 t")
        elif w == 2:
            a = 40.0 * t
            c = o + np.array([math.cos(a) * 0.003, math.sin(a) * 0.003])
            r = np.linalg.norm(pts[:, :2] - c, axis=1)
            check(np.allclose(r, 0.002, rtol=0, atol=1e-12), f"moving t={t}: the stirrer's points are not 2 mm from its orbiting axis (max off {np.abs(r - 0.002).max():.3g})")
            check(set(np.round(pts[:, 2], 12)) == {0.001, 0.016}, f"moving t={t}: the stirrer's ends are not at z = 1 and 16 mm")
            check(sum(1 for c in wall if c == 2) == 64, f"moving t={t}: the stirrer is not 64 quads")
        elif w == 3:
            a = 40.0 * t
            c = o + np.array([math.cos(a) * 0.003, math.sin(a) * 0.003])
            r = np.linalg.norm(pts[:, :2] - c, axis=1)
            check(np.allclose(r, 0.002, rtol=0, atol=1e-12) and np.allclose(pts[:, 2], 0.016, rtol=0, atol=1e-15),
                  f"moving t={t}: the stirrer's end cap is not the 2 mm disc at z = 16 mm on its axis")
            check(sum(1 for c in wall if c == 3) == 1, f"moving t={t}: the end cap is not one polygon")
        elif w == 4:
            r = np.linalg.norm(pts[:, :2] - o, axis=1)
            check(np.allclose(r, 0.012 + pts[:, 2] / 0.03 * 0.008, rtol=0, atol=1e-12), f"moving t={t}: the funnel's points are off the cone")
        elif w == 5:
            check(np.allclose(pts[:, 0], 0.0, atol=1e-15), f"moving t={t}: x- is not at x = 0")
        elif w == 6:
            check(np.allclose(pts[:, 0], 0.022, rtol=0, atol=1e-15), f"moving t={t}: x+ is not at x = 22 mm")
check(seen == set(range(9)), f"moving: walls never drawn: {set(range(9)) - seen}")

# A turning mesh: every vertex on the cube turned by OMEGA t.
fr = frames(mesh)
check(len(fr) == pvd_count(mesh, "particles") > 1, f"mesh: {len(fr)} wall frames for {pvd_count(mesh, 'particles')} particle frames")
for t, poly in fr:
    x = vtk_to_numpy(poly.GetPoints().GetData())
    wall, ids = cells(poly)
    check(names(poly) == ["box"], f"mesh: wall_names {names(poly)}")
    check(len(ids) == 48 and all(len(l) == 3 for l in ids), f"mesh t={t}: not the 48 triangles")
    a = -omega * t
    xb = np.stack([math.cos(a) * x[:, 0] - math.sin(a) * x[:, 1], math.sin(a) * x[:, 0] + math.cos(a) * x[:, 1], x[:, 2]], axis=1)
    check(np.allclose(np.abs(xb).max(axis=1), 0.015, rtol=0, atol=1e-12), f"mesh t={t}: vertices off the turned cube")
    if t > 0.0:
        check(not np.allclose(x, x0), f"mesh t={t}: the mesh did not turn")
    else:
        x0 = x.copy()

# Walls at rest: written once.
check(pvd_count(static, "walls") == 1 and pvd_count(static, "particles") > 1, f"static: {pvd_count(static, 'walls')} wall frames (expected 1)")

if fails:
    print("\n".join(fails))
    sys.exit(1)
print("walls VTK: moving walls, a turning mesh and walls at rest read back where their motion puts them")
