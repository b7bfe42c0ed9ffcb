#!/usr/bin/python3
"""A coupled scene's particle state as a DEM-only scene, to price the gas in one configuration.

usage: dem_only_state.py SCENE PARTICLES_DAT TIME OUT_SCENE

Writes OUT_SCENE: SCENE without its gas (the gas, drag and pressure-gradient modules and
the [gas], [gas.boundaries], [coupling] and [drag] tables) and without its particle
generators ([[lattices]], [[random_particles]], [[shells]], [[particles]]), and with one
[[particles]] entry per particle of PARTICLES_DAT's sample at TIME (positions,
velocities, angular velocities, radii and materials, to the last bit), stepped with the
table's time step (integrator.dt, in place of SCENE's dt and dt_divisor), the contacts
in the sample allowed (checks.allow_initial_overlap). Run from the
same particle state, the coupled scene (restarted from its checkpoint at TIME) and
OUT_SCENE give the cost of a coupled step against a DEM-only one in the same
configuration; the DEM-only run starts with no contact history, and without the gas
its bed starts to fall, so short windows compare best (bench/README, session 36).
"""
import re
import sys
import tomllib

DROPPED_TABLES = {"gas", "gas.boundaries", "coupling", "drag"}
DROPPED_ARRAYS = {"lattices", "random_particles", "shells", "particles"}
DROPPED_MODULE_KEYS = {"gas", "drag", "pressure_gradient"}


def fail(msg):
    sys.exit(f"dem_only_state.py: {msg}")


def without_gas(text, dt):
    """The scene's text without the gas tables, the gas modules and the particle
    generators, stepped with @p dt."""
    out, table, keep = [], "", True
    for line in text.splitlines():
        head = re.match(r"^\s*\[\[?\s*([A-Za-z0-9_.]+)\s*\]\]?", line)
        if head:
            table = head.group(1)
            keep = table not in DROPPED_TABLES and table not in DROPPED_ARRAYS
        key = re.match(r"^\s*([A-Za-z0-9_]+)\s*=", line)
        if keep and table == "modules" and key and key.group(1) in DROPPED_MODULE_KEYS:
            continue
        if keep and table == "integrator" and key and key.group(1) in ("dt", "dt_divisor"):
            continue
        if keep and table == "checks" and key and key.group(1) == "allow_initial_overlap":
            continue
        if head and table == "integrator":
            out.extend([line, f"dt = {dt!r}"])
            continue
        if head and table == "checks":  # the particles touch each other and the walls
            out.extend([line, "allow_initial_overlap = true"])
            continue
        if keep:
            out.append(line)
    return "\n".join(out).rstrip() + "\n"


def sample(path, time):
    """The rows of the sample at @p time and the material names, from a particles.dat."""
    materials, rows, columns, dt = {}, [], None, None
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                d = re.search(r"dt = ([0-9.eE+-]+) s", line)
                if d:
                    dt = float(d.group(1))
                m = re.search(r"materials: (.*)$", line)
                if m:
                    for item in m.group(1).split(","):
                        idx, name = item.split()
                        materials[int(idx)] = name
                elif line.startswith("# t[s]"):
                    columns = [c.split("[")[0] for c in line[1:].split()]
                continue
            v = line.split()
            if abs(float(v[0]) - time) <= 1e-12 * max(1.0, abs(time)):
                rows.append(dict(zip(columns, v)))
    if columns is None:
        fail(f"{path}: no column header ('# t[s] ...'): not a cdm particle table")
    if not rows:
        fail(f"{path}: no sample at t = {time!r} s")
    if dt is None:
        fail(f"{path}: no time step in the header ('dt = ... s')")
    return rows, materials, dt


def main():
    if len(sys.argv) != 5:
        fail("usage: dem_only_state.py SCENE PARTICLES_DAT TIME OUT_SCENE")
    scene, table, time, target = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
    with open(scene) as f:
        text = f.read()
    if tomllib.loads(text).get("units", "SI") != "SI":
        fail(f"{scene}: units = 'SI' expected (the table is SI)")
    rows, materials, dt = sample(table, time)
    if "integrator" not in tomllib.loads(text):
        fail(f"{scene}: no [integrator] table to give the time step")
    parts = [without_gas(text, dt)]
    if "checks" not in tomllib.loads(text):
        parts.append("\n[checks]\nallow_initial_overlap = true\n")
    for r in rows:
        # repr() of a float reads back as the same double: the state to the last bit.
        vec = lambda *k: "[" + ", ".join(repr(float(r[c])) for c in k) + "]"
        entry = (f'\n[[particles]]\nmaterial = "{materials[int(r["material"])]}"\nradius = {float(r["radius"])!r}\n'
                 f'position = {vec("x", "y", "z")}\nvelocity = {vec("vx", "vy", "vz")}\n')
        if "wx" in r:
            entry += f'angular_velocity = {vec("wx", "wy", "wz")}\n'
        parts.append(entry)
    with open(target, "w") as f:
        f.write("".join(parts))
    print(f"{target}: {len(rows)} particles at t = {time} s, without the gas")


if __name__ == "__main__":
    main()
