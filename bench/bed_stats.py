#!/usr/bin/python3
"""Pressure drop and bed height of a fluidised bed, from cdm's output or an OpenFOAM case.

    bed_stats.py cdm OUTDIR --axis z       cdm run -o OUTDIR with output.vtk (binary or ascii) and output.particles
    bed_stats.py openfoam CASE --axis z    a DPMFoam case written in ascii (last time directory)
    bed_stats.py openfoam CASE --axis z --probes
                                           the pressure drop only, at every step a `probes`
                                           function object on p wrote (postProcessing/*/*/p)

prints one line at the last written time (with --series, one per written time):

    t=<s> dp=<Pa> bed_height=<m> h99=<m>

With --window W the rows are averaged over windows of W seconds, [0, W), [W, 2W), ...
(a window holds the rows whose t lies in it), one line per window that holds rows:

    t0=<s> t1=<s> n=<rows> dp=<Pa> dp_sd=<Pa> bed_height=<m> h99=<m>

dp_sd is the standard deviation of the window's rows (not of its mean). DPMFoam's
pressure sampled at single steps is noisy (whole particles crossing cell faces), so
compare its windowed probes with cdm's windowed frames; --window with --probes and
--series is the time-averaged pressure drop of bench/README.md.

dp is the mean gas pressure of the lowest layer of cells minus that of the highest layer
(cell centres, so both codes are measured on the same points of the same grid). OpenFOAM's
incompressible p is kinematic (p/rho); it is multiplied by the gas density of
constant/transportProperties. bed_height is twice the mean particle centre height above
the bottom of the domain (the height of a bed of uniform density holding the same
particles); h99 is the 99th percentile of centre height plus radius.
"""
import argparse
import gzip
import math
import os
import re
import struct
import sys
import xml.etree.ElementTree as ET
import zlib

AXES = {"x": 0, "y": 1, "z": 2}


def fail(msg):
    sys.exit(f"bed_stats.py: {msg}")


def layer_dp(values, cells, axis):
    """Mean of the lowest minus mean of the highest layer along axis; values x fastest."""
    nx, ny, nz = cells
    n = [nx, ny, nz]
    if len(values) != nx * ny * nz:
        fail(f"{len(values)} cell values, expected {nx}*{ny}*{nz}")
    low, high, count = 0.0, 0.0, 0
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                idx = (i, j, k)[axis]
                v = values[i + nx * (j + ny * k)]
                if idx == 0:
                    low += v
                    count += 1
                elif idx == n[axis] - 1:
                    high += v
    return (low - high) / count


def heights(z, r, base):
    if not z:
        fail("no particles found")
    h = sorted(zi - base + ri for zi, ri in zip(z, r))
    mean = sum(zi - base for zi in z) / len(z)
    return 2.0 * mean, h[min(len(h) - 1, int(0.99 * len(h)))]


def vtk_file(path):
    """(XML root, {array name: list of floats}) of a VTK XML file: ascii, or appended raw
    data, zlib-compressed or not, as cdm writes it (Float64/Float32/Int32/Int64/UInt8)."""
    with open(path, "rb") as f:
        data = f.read()
    cut = data.find(b"<AppendedData")
    if cut < 0:
        root = ET.fromstring(data)
        return root, {a.get("Name"): [float(v) for v in (a.text or "").split()]
                      for a in root.iter("DataArray")}
    start = data.index(b"_", cut) + 1
    root = ET.fromstring(data[:cut] + b"</VTKFile>")
    head = {"UInt32": "<I", "UInt64": "<Q"}[root.get("header_type", "UInt32")]
    hsize = struct.calcsize(head)
    kinds = {"Float64": "d", "Float32": "f", "Int32": "i", "Int64": "q", "UInt8": "B"}
    arrays = {}
    for a in root.iter("DataArray"):
        pos = start + int(a.get("offset"))
        if root.get("compressor"):
            blocks = struct.unpack_from(head, data, pos)[0]
            sizes = struct.unpack_from("<" + head[1] * (3 + blocks), data, pos)[3:]
            pos += hsize * (3 + blocks)
            chunks = []
            for s in sizes:
                chunks.append(zlib.decompress(data[pos:pos + s]))
                pos += s
            raw = b"".join(chunks)
        else:
            n = struct.unpack_from(head, data, pos)[0]
            raw = data[pos + hsize:pos + hsize + n]
        kind = kinds[a.get("type")]
        arrays[a.get("Name")] = [float(v) for v in
                                 struct.unpack("<%d%s" % (len(raw) // struct.calcsize(kind), kind), raw)]
    return root, arrays


def cdm_stats(out, axis):
    """(t, dp, (bed_height, h99)) at every frame that has gas, particle VTK and particles.dat rows."""
    vtk = os.path.join(out, "vtk")
    gas = sorted(f for f in os.listdir(vtk) if f.startswith("gas_") and f.endswith(".vti"))
    if not gas:
        fail(f"no {vtk}/gas_*.vti (the scene needs output.vtk = true)")
    # particles.dat: one block of rows (t id x y z ...) per sample.
    samples, last_t = {}, None
    with open(os.path.join(out, "particles.dat")) as f:
        for line in f:
            if line.startswith("#"):
                continue
            cols = line.split()
            if cols[0] != last_t:
                last_t = cols[0]
                samples[float(last_t)] = []
            samples[float(last_t)].append(float(cols[2 + axis]))
    parts = sorted(f for f in os.listdir(vtk) if f.startswith("particles_") and f.endswith(".vtp"))
    rows = []
    for name in gas:
        root, arrays = vtk_file(os.path.join(vtk, name))
        image = root.find("ImageData")
        ext = [int(v) for v in image.get("WholeExtent").split()]
        cells = [ext[1] - ext[0], ext[3] - ext[2], ext[5] - ext[4]]
        base = float(image.get("Origin").split()[axis])
        t = arrays["TIME"][0]
        if "pressure" not in arrays:
            fail(f"{name} has no pressure array")
        dp = layer_dp(arrays["pressure"], cells, axis)
        z = next((zs for ts, zs in samples.items() if abs(ts - t) <= 1e-9), None)
        if z is None:
            fail(f"particles.dat has no sample at t = {t} (the gas frame {name})")
        frame = name[len("gas_"):-len(".vti")]
        pname = f"particles_{frame}.vtp" if f"particles_{frame}.vtp" in parts else parts[-1]
        radius = vtk_file(os.path.join(vtk, pname))[1]["radius"]
        if len(radius) != len(z):
            radius = [radius[0]] * len(z)
        rows.append((t, dp, heights(z, radius, base)))
    return rows


def foam_list(path):
    """The numbers of an ascii OpenFOAM field or cloud file (internalField or the top list)."""
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt") as f:
        text = f.read()
    m = re.search(r"internalField\s+nonuniform\s+List<scalar>\s*(\d+)\s*\((.*?)\)\s*;", text, re.S)
    if m:
        return [float(v) for v in m.group(2).split()]
    m = re.search(r"internalField\s+uniform\s+([-\d.eE+]+)", text)
    if m:
        return None
    return text


def foam_density(case):
    """The carrier gas's density, from constant/transportProperties (rho.<phase>)."""
    with open(os.path.join(case, "constant", "transportProperties")) as f:
        return float(re.search(r"rho\.\w+\s+(?:\[[^\]]*\]\s*)?([-\d.eE+]+)", f.read()).group(1))


def openfoam_stats(case, axis):
    """(t, dp, (bed_height, h99)) at every written time after 0."""
    times = [d for d in os.listdir(case) if re.fullmatch(r"[\d.eE+-]+", d) and float(d) > 0]
    if not times:
        fail(f"{case}: no time directory after 0")
    return [openfoam_time(case, tdir, axis) for tdir in sorted(times, key=float)]


def openfoam_time(case, tdir, axis):
    rho = foam_density(case)
    with open(os.path.join(case, "system", "blockMeshDict")) as f:
        bm = f.read()
    cells = [int(v) for v in re.search(r"hex\s*\([\d\s]+\)\s*\((\d+)\s+(\d+)\s+(\d+)\)",
                                       re.sub(r"//.*", "", bm)).groups()]
    scale = float(re.search(r"scale\s+([-\d.eE+]+)", bm).group(1))
    verts = re.findall(r"\(\s*([-\d.eE+]+)\s+([-\d.eE+]+)\s+([-\d.eE+]+)\s*\)",
                       bm.split("vertices", 1)[1].split("blocks", 1)[0])
    base = min(float(v[axis]) for v in verts) * scale
    p = foam_list(os.path.join(case, tdir, "p"))
    if not isinstance(p, list):
        fail(f"{case}/{tdir}/p: expected an ascii nonuniform field (writeFormat ascii)")
    dp = rho * layer_dp(p, cells, axis)
    cloud = os.path.join(case, tdir, "lagrangian", "kinematicCloud")
    text = foam_list(os.path.join(cloud, "positions"))
    # Legacy positions: "(x y z) celli" per parcel.
    pts = re.findall(r"\(\s*([-\d.eE+]+)\s+([-\d.eE+]+)\s+([-\d.eE+]+)\s*\)\s*-?\d+", text)
    z = [float(v[axis]) for v in pts]
    dtext = foam_list(os.path.join(cloud, "d")).split("FoamFile", 1)[-1].split("}", 1)[-1]
    uniform = re.search(r"(\d+)\s*\{\s*([-\d.eE+]+)\s*\}", dtext)  # N{value}: all equal
    listed = re.search(r"(\d+)\s*\((.*?)\)", dtext, re.S)
    if uniform:
        d = [float(uniform.group(2))] * int(uniform.group(1))
    else:
        d = [float(v) for v in listed.group(2).split()] if listed else []
    if len(d) != len(z):
        fail(f"{cloud}: {len(z)} positions but {len(d)} diameters")
    return float(tdir), dp, heights(z, [0.5 * v for v in d], base)


def openfoam_probes(case, axis):
    """(t, dp, (nan, nan)) at every probed step: the mean over the probes of the lowest
    probed layer minus the mean over those of the highest, times the gas density."""
    rho = foam_density(case)
    root = os.path.join(case, "postProcessing")
    def start(d):  # the time a function object's folder starts at (its name), else 0
        try:
            return float(os.path.basename(d))
        except ValueError:
            return 0.0
    dirs = [d for d, _, names in os.walk(root) if "p" in names] if os.path.isdir(root) else []
    files = [os.path.join(d, "p") for d in sorted(dirs, key=lambda d: (start(d), d))]
    if not files:
        fail(f"{case}: no postProcessing/*/*/p (a probes function object on p)")
    rows = {}
    for path in files:  # one file per restart time; a later start overrides the overlap
        height, values = [], []
        with open(path) as f:
            for line in f:
                m = re.match(r"#\s*Probe\s+\d+\s*\(\s*([-\d.eE+]+)\s+([-\d.eE+]+)\s+([-\d.eE+]+)\s*\)", line)
                if m:
                    height.append(float(m.group(1 + axis)))
                elif line.strip() and not line.startswith("#"):
                    values.append([float(v) for v in line.split()])
        if not height:
            fail(f"{path}: no '# Probe k (x y z)' header lines")
        low = [k for k, h in enumerate(height) if h == min(height)]
        high = [k for k, h in enumerate(height) if h == max(height)]
        if low == high:
            fail(f"{path}: the probes lie at one height: expected a lowest and a highest layer")
        for v in values:
            if len(v) != len(height) + 1:
                fail(f"{path}: a row of {len(v)} values, expected the time and {len(height)} probes")
            p = v[1:]
            dp = sum(p[k] for k in low) / len(low) - sum(p[k] for k in high) / len(high)
            rows[v[0]] = (v[0], rho * dp, (float("nan"), float("nan")))
    return [rows[t] for t in sorted(rows)]


def windows(rows, width):
    """The rows averaged over windows [k width, (k + 1) width): (t0, t1, n, dp, dp_sd, h, h99)."""
    groups = {}
    for t, dp, (h, h99) in rows:
        groups.setdefault(math.floor(t / width + 1e-9), []).append((dp, h, h99))  # t = k width lands in k
    out = []
    for k in sorted(groups):
        g = groups[k]
        n = len(g)
        mean = [sum(r[i] for r in g) / n for i in range(3)]
        sd = (sum((r[0] - mean[0]) ** 2 for r in g) / (n - 1)) ** 0.5 if n > 1 else 0.0
        out.append((k * width, (k + 1) * width, n, mean[0], sd, mean[1], mean[2]))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("code", choices=["cdm", "openfoam"])
    ap.add_argument("dir")
    ap.add_argument("--axis", choices=sorted(AXES), default="z", help="the vertical axis")
    ap.add_argument("--series", action="store_true", help="one line per written time, not the last only")
    ap.add_argument("--probes", action="store_true", help="openfoam: the pressure drop from the p probes, every step")
    ap.add_argument("--window", type=float, help="average the rows over windows of this many seconds")
    a = ap.parse_args()
    if a.probes and a.code != "openfoam":
        fail("--probes reads an OpenFOAM case's probes: expected the code openfoam")
    if a.window is not None and not a.window > 0.0:
        fail(f"--window {a.window}: expected a window longer than 0 s")
    stats = openfoam_probes if a.probes else cdm_stats if a.code == "cdm" else openfoam_stats
    rows = stats(a.dir, AXES[a.axis])
    if a.window is not None:
        for t0, t1, n, dp, sd, h, h99 in windows(rows, a.window):
            print(f"t0={t0:.6g} t1={t1:.6g} n={n} dp={dp:.6g} dp_sd={sd:.6g} bed_height={h:.6g} h99={h99:.6g}")
        return
    for t, dp, (h, h99) in (rows if a.series else rows[-1:]):
        print(f"t={t:.6g} dp={dp:.6g} bed_height={h:.6g} h99={h99:.6g}")


if __name__ == "__main__":
    main()
