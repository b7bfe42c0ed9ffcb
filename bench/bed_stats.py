#!/usr/bin/python3
"""Pressure drop and bed height of a fluidised bed, from cdm's output or an OpenFOAM case.

    bed_stats.py cdm OUTDIR --axis z       cdm run -o OUTDIR with output.vtk (binary or ascii) and output.particles
    bed_stats.py openfoam CASE --axis z    a DPMFoam case written in ascii (last time directory)

prints one line at the last written time (with --series, one per written time):

    t=<s> dp=<Pa> bed_height=<m> h99=<m>

dp is the mean gas pressure of the lowest layer of cells minus that of the highest layer
(cell centres, so both codes are measured on the same points of the same grid). OpenFOAM's
incompressible p is kinematic (p/rho); it is multiplied by the gas density of
constant/transportProperties. bed_height is twice the mean particle centre height above
the bottom of the domain (the height of a bed of uniform density holding the same
particles); h99 is the 99th percentile of centre height plus radius.
"""
import argparse
import gzip
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


def openfoam_stats(case, axis):
    """(t, dp, (bed_height, h99)) at every written time after 0."""
    times = [d for d in os.listdir(case) if re.fullmatch(r"[\d.eE+-]+", d) and float(d) > 0]
    if not times:
        fail(f"{case}: no time directory after 0")
    return [openfoam_time(case, tdir, axis) for tdir in sorted(times, key=float)]


def openfoam_time(case, tdir, axis):
    with open(os.path.join(case, "constant", "transportProperties")) as f:
        rho = float(re.search(r"rho\.\w+\s+(?:\[[^\]]*\]\s*)?([-\d.eE+]+)", f.read()).group(1))
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


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("code", choices=["cdm", "openfoam"])
    ap.add_argument("dir")
    ap.add_argument("--axis", choices=sorted(AXES), default="z", help="the vertical axis")
    ap.add_argument("--series", action="store_true", help="one line per written time, not the last only")
    a = ap.parse_args()
    stats = cdm_stats if a.code == "cdm" else openfoam_stats
    rows = stats(a.dir, AXES[a.axis])
    for t, dp, (h, h99) in (rows if a.series else rows[-1:]):
        print(f"t={t:.6g} dp={dp:.6g} bed_height={h:.6g} h99={h99:.6g}")


if __name__ == "__main__":
    main()
