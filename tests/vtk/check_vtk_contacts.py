#!/usr/bin/python3
"""Reads back the per-contact VTK files (output.contacts) of a settling bed: one frame per
particle frame in contacts.pvd; each line joins two particles that overlap by the
recorded amount (r_i + r_j - |x_j - x_i|, from the particle frame's positions and radii);
the normal force lies along the line (pushing the particles apart in most contacts);
the tangential force is perpendicular to it; and the contacts' forces, with the wall
contacts (the particle's total contact force less its pairs), add up to each particle's
contact_force of the particle frame: a particle touching no wall gets exactly its pairs."""
import glob
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

out = sys.argv[1]
fails = []


def check(cond, what):
    if not cond:
        fails.append(what)


def poly(path):
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


pframes = sorted(glob.glob(f"{out}/vtk/particles_*.vtp"))
cframes = sorted(glob.glob(f"{out}/vtk/contacts_*.vtp"))
check(len(cframes) == len(pframes) > 0, f"{len(cframes)} contact frames for {len(pframes)} particle frames")
check(open(f"{out}/contacts.pvd").read().count("<DataSet") == len(cframes), "contacts.pvd does not list every frame")
total_contacts = 0
for pf, cf in zip(pframes, cframes):
    p, c = poly(pf), poly(cf)
    x = vtk_to_numpy(p.GetPoints().GetData())
    r = vtk_to_numpy(p.GetPointData().GetArray("radius"))
    fc = vtk_to_numpy(p.GetPointData().GetArray("contact_force"))
    check(np.array_equal(vtk_to_numpy(c.GetPoints().GetData()), x), f"{cf}: points are not the particles")
    n = c.GetNumberOfLines()
    total_contacts += n
    if n == 0:
        continue
    ij = vtk_to_numpy(c.GetCellData().GetArray("particles")).reshape(-1, 2)
    fn = vtk_to_numpy(c.GetCellData().GetArray("normal_force"))
    ft = vtk_to_numpy(c.GetCellData().GetArray("tangential_force"))
    ov = vtk_to_numpy(c.GetCellData().GetArray("overlap"))
    d = x[ij[:, 1]] - x[ij[:, 0]]
    dist = np.linalg.norm(d, axis=1)
    check(np.all(ov > 0), f"{cf}: a contact without overlap")
    check(np.allclose(ov, r[ij[:, 0]] + r[ij[:, 1]] - dist, rtol=0, atol=1e-15), f"{cf}: overlap is not the geometry's")
    eta = d / dist[:, None]
    along = np.sum(fn * eta, axis=1)
    # (A separating contact's dashpot may pull: the linear law is not clipped.)
    check(np.any(along < 0), f"{cf}: no contact pushes its particles apart")
    check(np.allclose(np.linalg.norm(fn - along[:, None] * eta, axis=1), 0, atol=1e-12 * np.abs(along).max()),
          f"{cf}: a normal force off the line of centres")
    check(np.allclose(np.sum(ft * eta, axis=1), 0, atol=1e-9 * np.abs(along).max()),
          f"{cf}: a tangential force with a normal part")
    pair_sum = np.zeros_like(fc)
    f = fn + ft
    np.add.at(pair_sum, ij[:, 0], f)
    np.add.at(pair_sum, ij[:, 1], -f)
    # Walls push along their normals (z here, the bed's floor and sides along x, y): the
    # difference, per particle, is its wall contacts; the particles off the walls have none.
    rest = fc - pair_sum
    lo, hi = x.min(axis=0), x.max(axis=0)
    inner = np.all((x - r[:, None] > lo + 1e-3) & (x + r[:, None] < hi - 1e-3), axis=1)
    scale = np.abs(fc).max()
    check(np.allclose(rest[inner], 0, atol=1e-12 * scale), f"{cf}: pair forces do not add up to contact_force")
check(total_contacts > 0, "no contacts in any frame")
if fails:
    print("\n".join(fails))
    sys.exit(1)
print(f"contacts: {len(cframes)} frames, {total_contacts} contacts, all consistent")
