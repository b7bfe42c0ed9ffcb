#!/usr/bin/python3
"""dem_only_state.py: the DEM-only scene starts from the coupled run's sample, to the bit.

usage: test_dem_only_state.py CDM DEM_ONLY_STATE_PY SOURCE_DIR WORK_DIR

Runs the Müller bed (gas, two-way drag) for 120 steps with its particle table sampled
every 1e-4 s, turns the last sample into a DEM-only scene, and runs that scene for one
step: its table's first sample (t = 0) must hold the same particles as the coupled
sample, column for column as written, and the scene must have no gas. A time with no
sample must be refused.
"""
import os
import shutil
import subprocess
import sys
import tomllib


def rows(path, time=None):
    """The rows of particles.dat's sample at @p time (its first sample if None), without t."""
    out, first = [], None
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                continue
            v = line.split()
            first = v[0] if first is None else first
            if v[0] == (time if time is not None else first):
                out.append(v[1:])
    return out


def main():
    cdm, tool, src, work = sys.argv[1:5]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    scene = f"{src}/bench/scenes/mueller_bubbling_bed.toml"
    run = lambda *a: subprocess.run([cdm, "run", *a, "-q", "-j", "1"], check=True, capture_output=True, text=True)
    run(scene, "--max-steps", "120", "--set", "output.interval=1.0e-4", "--set", "output.particles=true",
        "--set", "output.vtk=false", "-o", f"{work}/coupled")
    with open(f"{work}/coupled/particles.dat") as f:
        last_t = [l.split()[0] for l in f if not l.startswith("#")][-1]
    if float(last_t) <= 0.0:
        sys.exit(f"FAIL: the coupled run's last sample is at t = {last_t}, not after the start")
    subprocess.run(["/usr/bin/python3", tool, scene, f"{work}/coupled/particles.dat", last_t, f"{work}/dem.toml"],
                   check=True)
    run(f"{work}/dem.toml", "--max-steps", "1", "--set", "output.particles=true", "--set", "output.vtk=false",
        "-o", f"{work}/dem")
    coupled, dem = rows(f"{work}/coupled/particles.dat", last_t), rows(f"{work}/dem/particles.dat")
    if len(coupled) != 9240 or coupled != dem:
        bad = next((i for i, (a, b) in enumerate(zip(coupled, dem)) if a != b), min(len(coupled), len(dem)))
        sys.exit(f"FAIL: {len(coupled)} coupled rows, {len(dem)} DEM-only rows; first difference at row {bad}")
    with open(f"{work}/dem.toml", "rb") as f:
        dem_scene = tomllib.load(f)
    gas_left = [k for k in ("gas", "drag", "pressure_gradient") if k in dem_scene["modules"]]
    gas_left += [t for t in ("gas", "coupling", "drag") if t in dem_scene]
    if gas_left:
        sys.exit(f"FAIL: the DEM-only scene still has {gas_left}")
    refused = subprocess.run(["/usr/bin/python3", tool, scene, f"{work}/coupled/particles.dat", "0.5", f"{work}/x.toml"],
                             capture_output=True, text=True)
    if refused.returncode == 0 or "no sample at t = 0.5" not in refused.stderr or os.path.exists(f"{work}/x.toml"):
        sys.exit(f"FAIL: a time with no sample was not refused: {refused.returncode} {refused.stderr}")
    print(f"ok: {len(dem)} particles at t = {last_t} s, the same in the DEM-only scene")


if __name__ == "__main__":
    main()
