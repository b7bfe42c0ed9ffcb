#!/usr/bin/python3
"""Every scene cdm ships, on several processes, against one process: byte for byte.

Runs each scene of examples/ and bench/scenes/ and every variant of every verification
case (the case's scene with the variant's overrides) for a fixed number of steps, logged
at every step, on one process without a launcher and on NP processes under mpirun, and
compares every file the two runs wrote. Results must be identical (the shared step,
rank_split.hpp).

usage: mpi_audit.py [--gas-planes] CDM SOURCE_DIR WORK_DIR [NP [STEPS [FILTER...]]]

With --gas-planes only the scenes with a solved gas run, with gas.division = "planes", so
that their gas step is divided (each process reading the planes under its particles)
however small their grid. Each runs as written and in the variants that take other paths
through the divided step: on grids of at most 20000 cells (where the direct solve's
factorisations stay quick; larger ones solve by multigrid), with each pressure solve
named, "multigrid" and "direct"; and, where the particles' drag is updated explicitly on
a two-way gas, with drag.update = "exponential", which makes the gas take the drag
implicitly (coupling.gas_drag's default).

A scene whose one-process run fails (a mesh the benchmarks generate first) is listed as
skipped; a failure on NP processes, or any file that differs, fails the audit.
"""
import filecmp
import glob
import os
import shutil
import subprocess
import sys
import tomllib


def scenes(root):
    """(tag, scene file, overrides) for every scene and every case variant."""
    for s in sorted(glob.glob(f"{root}/examples/*/*.toml") + glob.glob(f"{root}/bench/scenes/*.toml")):
        yield os.path.relpath(s, root), s, []
    for c in sorted(glob.glob(f"{root}/verification/cases/*/case.toml")):
        d = os.path.dirname(c)
        with open(c, "rb") as f:
            case = tomllib.load(f)
        for v in case.get("variants", [{"name": "base", "set": []}]):
            scene = os.path.join(d, v.get("scene", case.get("scene", "scene.toml")))
            yield f"{os.path.basename(d)}/{v.get('name', 'base')}", scene, v.get("set", [])


def gas_variants(scene, sets):
    """(suffix, overrides) of a solved-gas scene's runs with --gas-planes."""
    with open(scene, "rb") as f:
        spec = tomllib.load(f)
    yield "", []
    cells = 1
    for n in spec.get("gas", {}).get("cells", [1]):
        cells *= n
    if cells <= 20000:
        yield "+multigrid", ['gas.pressure_solver="multigrid"']
        yield "+direct", ['gas.pressure_solver="direct"']
    # The keys as the case's overrides leave them (one key, or a whole table inline).
    key = {"drag.update": spec.get("drag", {}).get("update", ""),
           "coupling.mode": spec.get("coupling", {}).get("mode", ""),
           "coupling.method": spec.get("coupling", {}).get("method", "")}
    for x in sets:
        k, _, v = x.partition("=")
        try:
            value = tomllib.loads(f"v = {v}")["v"]
        except tomllib.TOMLDecodeError:
            value = v
        for name in key:
            if k == name:
                key[name] = value
            elif isinstance(value, dict) and name.startswith(k + ".") and name[len(k) + 1:] in value:
                key[name] = value[name[len(k) + 1:]]
    # Not where the drag's update must stay explicit: on fixed particles, or a drag that
    # does not read the particle's own velocity (cell averages).
    fixed = any(m.get("fixed", False) for m in spec.get("materials", []))
    if (key["coupling.mode"] == "two_way" and key["drag.update"] == "explicit" and not fixed
            and key["coupling.method"] != "cell_average"):
        yield "+implicit", ['drag.update="exponential"']


def runs(root, planes):
    """(tag, scene file, overrides) of every run: with --gas-planes, each solved-gas scene
    and its variants (gas_variants), divided by planes."""
    for tag, scene, sets in scenes(root):
        if not planes:
            yield tag, scene, sets
            continue
        if 'gas = "solved"' not in open(scene).read():
            continue
        for suffix, more in gas_variants(scene, sets):
            yield tag + suffix, scene, ['gas.division="planes"'] + sets + more


def main():
    argv = sys.argv[1:]
    planes = argv[:1] == ["--gas-planes"]
    if planes:
        argv = argv[1:]
    cdm, root, work = argv[0:3]
    np_ = argv[3] if len(argv) > 3 else "2"
    steps = argv[4] if len(argv) > 4 else "1500"
    only = argv[5:]
    launch = ["mpirun", "--oversubscribe", "-np", np_]
    if os.geteuid() == 0:
        launch.insert(1, "--allow-run-as-root")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(f"{work}/tmp")
    env = dict(os.environ, TMPDIR=f"{work}/tmp")
    failed, skipped, same = [], [], 0
    for tag, scene, sets in runs(root, planes):
        if only and not any(o in tag for o in only):
            continue
        args = ["run", scene, "-q", "-j", "1", "--max-steps", steps,
                "--set", "output.interval=1.0e-3", "--set", "output.log_interval=1.0e-9"]
        text = open(scene).read()
        for x in sets:
            # A case's overrides of walls[...] or meshes[...] address its reference scene.
            if (x.startswith("walls[") and "[[walls]]" not in text) or (x.startswith("meshes[") and "[[meshes]]" not in text):
                continue
            args += ["--set", x]
        out = f"{work}/{tag.replace('/', '_')}"
        one = subprocess.run([cdm] + args + ["-o", out + "-1"], capture_output=True, text=True, env=env)
        if one.returncode != 0:
            skipped.append(f"{tag}: {one.stderr.strip()[-160:]}")
            continue
        many = subprocess.run(launch + [cdm] + args + ["-o", out + "-n"], capture_output=True, text=True, env=env)
        if many.returncode != 0:
            failed.append(f"{tag}: {np_} processes failed: {many.stderr.strip()[-300:]}")
            continue
        files = sorted(os.path.relpath(f, out + "-1") for f in glob.glob(out + "-1/**", recursive=True) if os.path.isfile(f))
        others = sorted(os.path.relpath(f, out + "-n") for f in glob.glob(out + "-n/**", recursive=True) if os.path.isfile(f))
        differ = [f for f in files if f not in others or not filecmp.cmp(f"{out}-1/{f}", f"{out}-n/{f}", shallow=False)]
        if differ or files != others:
            failed.append(f"{tag}: differs from one process's: {' '.join(differ[:5]) or 'not the same files'}")
        else:
            same += 1
        shutil.rmtree(out + "-1"); shutil.rmtree(out + "-n")
        print(f"{tag}: {'shared' if 'shared among' in many.stdout + many.stderr else 'whole'} "
              f"{'differs' if differ else 'same'}", flush=True)
    for s in skipped:
        print("skipped (one process failed):", s)
    for f in failed:
        print("FAILED", f)
    print(f"mpi_audit: {same} scenes identical on {np_} processes over {steps} steps, {len(failed)} failed, {len(skipped)} skipped")
    sys.exit(1 if failed or not same else 0)


if __name__ == "__main__":
    main()
