#!/usr/bin/python3
"""Reads back the VTK files of a settling bed (two materials, friction, walls) written
binary and ASCII: both agree with the particle table to the bit (id, material and its
names, radius, position, velocity, angular velocity), carry the same contact forces,
some of them non-zero, and the binary files are at most a third of the ASCII ones."""
import glob
import os
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

binary, ascii_ = sys.argv[1], sys.argv[2]
fails = []


def check(cond, what):
    if not cond:
        fails.append(what)


# t id x y z vx vy vz wx wy wz radius material
rows = np.loadtxt(f"{binary}/particles.dat")
times = sorted(set(rows[:, 0]))
frames = sorted(glob.glob(f"{binary}/vtk/particles_*.vtp"))
check(len(frames) == len(times), f"{len(frames)} frames, the table has {len(times)} samples")


def read(path):
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    pd = r.GetOutput()
    a = {n: vtk_to_numpy(pd.GetPointData().GetArray(n))
         for n in ("id", "material", "radius", "velocity", "angular_velocity", "contact_force")
         if pd.GetPointData().GetArray(n) is not None}
    a["position"] = vtk_to_numpy(pd.GetPoints().GetData())
    names = pd.GetFieldData().GetAbstractArray("material_names")
    a["names"] = [names.GetValue(k) for k in range(names.GetNumberOfValues())] if names else []
    return a


loaded = 0
for f, t in zip(frames, times):
    b, a = read(f), read(f.replace(binary, ascii_, 1))
    table = rows[rows[:, 0] == t]
    name = os.path.basename(f)
    for key in ("id", "material", "radius", "velocity", "angular_velocity", "contact_force", "position"):
        check(key in b, f"{name}: no {key}")
        check(key in a and np.array_equal(a[key], b[key]), f"{name}: {key} differs between binary and ASCII")
    if len(fails):
        break
    check(b["names"] == ["glass", "wall"], f"{name}: material_names {b['names']}")
    check(np.array_equal(b["id"], table[:, 1]), f"{name}: ids")
    check(np.array_equal(b["position"], table[:, 2:5]), f"{name}: positions")
    check(np.array_equal(b["velocity"], table[:, 5:8]), f"{name}: velocities")
    check(np.array_equal(b["angular_velocity"], table[:, 8:11]), f"{name}: angular velocities")
    check(np.array_equal(b["radius"], table[:, 11]), f"{name}: radii")
    check(np.array_equal(b["material"], table[:, 12]), f"{name}: materials")
    check(np.isfinite(b["contact_force"]).all(), f"{name}: non-finite contact force")
    loaded += 1
check(np.abs(read(frames[-1])["contact_force"]).max() > 0, "no contact force in the last frame")


def size(d):
    return sum(os.path.getsize(p) for p in glob.glob(f"{d}/vtk/*"))


sb, sa = size(binary), size(ascii_)
check(3 * sb <= sa, f"binary files {sb} B, more than a third of the ASCII ones ({sa} B)")
if fails:
    print(f"check_vtk_settle: {len(fails)} failure(s):")
    for f in fails[:20]:
        print("  " + f)
    sys.exit(1)
print(f"check_vtk_settle: {loaded} frames of 2000 particles agree with the table, binary and ASCII alike; "
      f"binary {sb} B = {sb / sa:.2f} of ASCII {sa} B")
