#!/usr/bin/python3
"""Checks a finished run of bench/scenes/mueller_bubbling_bed.toml (CTest long.mueller_bubbling_bed).

The bed has no oracle; what any fluidised bed must show is checked from the VTK output:
1. averaged over the bubbling period (t >= T0), the gas pressure drop from the distributor
   to above the bed carries the bed: within 10 % of its buoyant weight per area (the
   time average of a momentum balance whose other terms — wall friction of the
   particles, gas acceleration, the particles' own mean acceleration — average out or
   are small; a fixed bed held by the distributor, or an inflow throttled by the bed,
   gives a far smaller drop);
2. the bed is expanded: its mean particle height, averaged over the period, at least
   5 % above that of the same spheres packed at solids fraction 0.6 (a fixed bed at
   random loose packing, 0.58, would be 3.5 % above);
3. it bubbles rather than expands smoothly: the pressure drop fluctuates, its standard
   deviation over the period at least 5 % of its mean (Müller et al. 2008 measured
   fluctuations of tens of per cent at twice U_mf).
Usage: bubbling_bed_check.py OUTDIR
"""
import glob
import math
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

T0 = 0.2          # s, start of the averaging period (bed fallen, fluidised)
INTERVAL = 0.05   # s, output.interval of the scene
N, D, RHO_P, RHO_G, G = 9240, 1.2e-3, 1000.0, 1.205, 9.81
WIDTH, DEPTH = 0.044, 0.01
PROBE = 0.09      # m, height of the upper pressure probe (above the bed)


def main(out):
    parts = sorted(glob.glob(out + "/vtk/particles_*.vtp"))
    gases = sorted(glob.glob(out + "/vtk/gas_*.vt*"))
    if len(parts) < 2 or len(parts) != len(gases):
        sys.exit(f"{out}/vtk: expected matching particle and gas files, found {len(parts)} and {len(gases)}")
    weight = N * math.pi / 6 * D**3 * (RHO_P - RHO_G) * G / (WIDTH * DEPTH)
    packed_mean_height = 0.5 * N * math.pi / 6 * D**3 / 0.6 / (WIDTH * DEPTH)
    dps, heights = [], []
    print(f"# t[s] dp[Pa] mean_height[mm]   (buoyant weight per area {weight:.1f} Pa)")
    for n, (pf, gf) in enumerate(zip(parts, gases)):
        t = n * INTERVAL
        r = vtk.vtkXMLPolyDataReader()
        r.SetFileName(pf)
        r.Update()
        y = vtk_to_numpy(r.GetOutput().GetPoints().GetData())[:, 1]
        rg = vtk.vtkXMLImageDataReader() if gf.endswith(".vti") else vtk.vtkXMLRectilinearGridReader()
        rg.SetFileName(gf)
        rg.Update()
        grid = rg.GetOutput()
        nx, ny, nz = (x - 1 for x in grid.GetDimensions())
        p = vtk_to_numpy(grid.GetCellData().GetArray("pressure")).reshape(nz, ny, nx).mean(axis=(0, 2))
        bounds = grid.GetBounds()
        h = (bounds[3] - bounds[2]) / ny
        row = int(PROBE / h)
        # The distributor pressure: the bottom row extrapolated to y = 0 with the bottom two rows.
        p0 = p[0] - 0.5 * (p[1] - p[0])
        dp = p0 - (p[row] + (PROBE - (row + 0.5) * h) * (p[row + 1] - p[row]) / h)
        print(f"{t:.2f} {dp:.2f} {y.mean() * 1e3:.2f}")
        if t >= T0 - 1e-9:
            dps.append(dp)
            heights.append(y.mean())
    if len(dps) < 3:
        sys.exit(f"only {len(dps)} outputs after t = {T0} s: the run is too short to judge")
    dps, heights = np.array(dps), np.array(heights)
    fails = []
    if abs(dps.mean() / weight - 1) > 0.10:
        fails.append(f"mean pressure drop {dps.mean():.1f} Pa is not within 10 % of the buoyant weight per area {weight:.1f} Pa")
    if heights.mean() < 1.05 * packed_mean_height:
        fails.append(f"mean particle height {heights.mean()*1e3:.2f} mm is not 5 % above the packed bed's {packed_mean_height*1e3:.2f} mm")
    if dps.std() < 0.05 * dps.mean():
        fails.append(f"pressure drop std {dps.std():.1f} Pa is below 5 % of its mean: the bed does not bubble")
    print(f"mean dp {dps.mean():.1f} Pa ({dps.mean() / weight:.3f} of the weight), std {dps.std():.1f} Pa; "
          f"mean height {heights.mean()*1e3:.2f} mm (packed {packed_mean_height*1e3:.2f} mm)")
    for f in fails:
        print("FAIL:", f)
    sys.exit(1 if fails else 0)


if __name__ == "__main__":
    main(sys.argv[1])
