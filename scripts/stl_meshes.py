#!/usr/bin/env python3
"""STL meshes for cdm's mesh-wall cases, benchmark and examples (standard library only).

Every mesh is built from a list of triangles and written as ASCII or binary STL. The
generators are deterministic (fixed seeds), so running this script again rewrites the
committed files byte for byte.

Usage: stl_meshes.py verification   writes the verification cases' meshes
       stl_meshes.py bench          writes bench/scenes/meshes/box_settle1e4.stl, box_settle1e5.stl
       stl_meshes.py hopper         writes examples/hopper/hopper.stl
       stl_meshes.py chute          writes bench/scenes/meshes/chute_sides.stl
       stl_meshes.py silo [OUT.stl ORIFICE_DIAMETER]
                                    writes examples/silo/silo.stl (orifice 32 mm), or the
                                    silo with the given orifice [m] to OUT.stl as ASCII
       stl_meshes.py all
"""
import math
import os
import random
import struct
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def write_ascii(path, tris, name="mesh"):
    with open(path, "w") as f:
        f.write(f"solid {name}\n")
        for a, b, c in tris:
            n = normal(a, b, c)
            f.write(f"facet normal {n[0]:.17g} {n[1]:.17g} {n[2]:.17g}\n outer loop\n")
            for v in (a, b, c):
                f.write(f"  vertex {v[0]:.17g} {v[1]:.17g} {v[2]:.17g}\n")
            f.write(" endloop\nendfacet\n")
        f.write(f"endsolid {name}\n")


def write_binary(path, tris, exact=True, header=b"cdm scripts/stl_meshes.py"):
    """Binary STL stores float32. With exact, every coordinate must be one float32 holds
    exactly (the verification meshes use multiples of powers of two), so the file is the
    mesh intended to the bit."""
    with open(path, "wb") as f:
        f.write(header.ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for a, b, c in tris:
            for v in (a, b, c) if exact else ():
                for x in v:
                    assert struct.unpack("<f", struct.pack("<f", x))[0] == x, f"{x} is not a float32"
            f.write(struct.pack("<12fH", *normal(a, b, c), *a, *b, *c, 0))


def normal(a, b, c):
    u = [b[i] - a[i] for i in range(3)]
    w = [c[i] - a[i] for i in range(3)]
    n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
    s = math.sqrt(sum(x * x for x in n))
    return [x / s for x in n]


def grid(n, lo, hi, place, jitter=0.0, seed=1, diagonal="alternate"):
    """An n x n grid of squares over [lo, hi]^2, two triangles each; place(u, v) maps the
    grid's coordinates to 3D. Interior points move by up to jitter cells (in-plane).
    diagonal: "alternate" flips the diagonal from square to square, "rising" keeps it along
    (1, 1)."""
    rng = random.Random(seed)
    h = (hi - lo) / n
    pts = {}
    for i in range(n + 1):
        for j in range(n + 1):
            u, v = lo + i * h, lo + j * h
            if jitter and 0 < i < n and 0 < j < n:
                # Multiples of 2^-20: exact in float32 and double.
                u += round(rng.uniform(-jitter, jitter) * h * 2**20) / 2**20
                v += round(rng.uniform(-jitter, jitter) * h * 2**20) / 2**20
            pts[i, j] = place(u, v)
    tris = []
    for i in range(n):
        for j in range(n):
            a, b, c, d = pts[i, j], pts[i + 1, j], pts[i + 1, j + 1], pts[i, j + 1]
            if diagonal == "rising" or (i + j) % 2 == 0:
                tris += [(a, b, c), (a, c, d)]
            else:
                tris += [(a, b, d), (b, c, d)]
    return tris


def box(lo, hi, n):
    """The six faces of the box [lo, hi] (3-vectors), each an n x n grid of squares."""
    tris = []
    for axis in range(3):
        for side in (0, 1):
            a1, a2 = (axis + 1) % 3, (axis + 2) % 3
            fixed = (lo, hi)[side][axis]

            def place(u, v, axis=axis, a1=a1, a2=a2, fixed=fixed):
                p = [0.0, 0.0, 0.0]
                p[axis] = fixed
                p[a1] = lo[a1] + u * (hi[a1] - lo[a1])
                p[a2] = lo[a2] + v * (hi[a2] - lo[a2])
                return tuple(p)

            tris += grid(n, 0.0, 1.0, place)
    return tris


def verification():
    cases = os.path.join(ROOT, "verification", "cases")
    flat = lambda u, v: (u, v, 0.0)
    # mesh_plane: two triangles; ~10^4 jittered triangles; a regular grid whose diagonals
    # all rise along (1, 1), so a sphere moving along x = y runs on edges through vertices.
    d = os.path.join(cases, "mesh_plane")
    write_ascii(os.path.join(d, "plane_2.stl"), grid(1, -0.5, 0.5, flat), "plane_2")
    write_binary(os.path.join(d, "plane_fine.stl"), grid(72, -0.5625, 0.5625, flat, jitter=0.3, seed=35))
    write_binary(os.path.join(d, "plane_grid.stl"), grid(32, -0.5, 0.5, flat, diagonal="rising"))
    # mesh_corner: a floor z = 0 (x >= 0) and a wall x = 0 (z >= 0) meeting at a concave
    # 90-degree edge along y, 8 x 8 squares each.
    d = os.path.join(cases, "mesh_corner")
    floor = grid(8, 0.0, 0.5, lambda u, v: (u, v - 0.25, 0.0))
    wall = grid(8, 0.0, 0.5, lambda u, v: (0.0, v - 0.25, u))
    write_ascii(os.path.join(d, "corner.stl"), floor + wall, "corner")
    # mesh_edge_impact: the cube [-0.05, 0.05]^3, 2 x 2 squares per face (48 triangles).
    d = os.path.join(cases, "mesh_edge_impact")
    write_ascii(os.path.join(d, "cube.stl"), box((-0.05,) * 3, (0.05,) * 3, 2), "cube")


def open_box(lo, hi, n):
    """The box [lo, hi] without its top face (z = hi[2])."""
    tris = box(lo, hi, n)
    return [t for t in tris if not all(v[2] == hi[2] for v in t)]


def bench():
    # The settle benchmark's walls (bench/scenes/settle_1e4.toml: floor z = 0, sides
    # x = 0, x = Lx, y = 0, y = Ly, open top) as a mesh, 32 x 32 squares per face: 10,240
    # triangles. Lx, Ly = 1.1 mm times the lattice's count: 20 x 20 (1e4) and 50 x 80 (1e5).
    d = os.path.join(ROOT, "bench", "scenes", "meshes")
    os.makedirs(d, exist_ok=True)
    for name, lx, ly in (("box_settle1e4.stl", 0.022, 0.022), ("box_settle1e5.stl", 0.055, 0.088)):
        write_binary(os.path.join(d, name), open_box((0.0, 0.0, 0.0), (lx, ly, 0.035), 32), exact=False)


def hopper():
    """A conical hopper for examples/hopper: a cone from an outlet of radius 12 mm at z = 0
    up to radius 60 mm at z = 0.1 m (a 64-degree cone, 25.6 degrees from the vertical),
    under a cylinder up to z = 0.25 m; 64 segments around, 6,144 triangles, binary."""
    segs, rings_cone, rings_cyl = 64, 12, 36
    r_top, r_out, h_cone, h_cyl = 0.06, 0.012, 0.1, 0.15
    tris = []

    def ring(r, z):
        return [(r * math.cos(2 * math.pi * k / segs), r * math.sin(2 * math.pi * k / segs), z) for k in range(segs)]

    profile = [(r_out + (r_top - r_out) * i / rings_cone, h_cone * i / rings_cone) for i in range(rings_cone + 1)]
    profile += [(r_top, h_cone + h_cyl * i / rings_cyl) for i in range(1, rings_cyl + 1)]
    rings = [ring(r, z) for r, z in profile]
    for lower, upper in zip(rings, rings[1:]):
        for k in range(segs):
            a, b = lower[k], lower[(k + 1) % segs]
            c, d = upper[(k + 1) % segs], upper[k]
            tris += [(a, b, c), (a, c, d)]
    d = os.path.join(ROOT, "examples", "hopper")
    os.makedirs(d, exist_ok=True)
    write_binary(os.path.join(d, "hopper.stl"), tris, exact=False)


def chute():
    """The side walls of the chute with mesh walls (bench/scenes/chute_mesh.toml): the
    planes y = 0 and y = 0.022 m over x = 0 ... 0.044 m (the chute's period) and
    z = 0 ... 0.08 m, each a grid of 2 mm squares (22 x 40, diagonals alternating):
    3,520 triangles, so the beads' contacts run across edges and vertices. ASCII, as LIGGGHTS
    reads the same file."""
    tris = []
    nx, nz, h = 22, 40, 0.002
    for y in (0.0, 0.022):
        for i in range(nx):
            for k in range(nz):
                a, b = (i * h, y, k * h), ((i + 1) * h, y, k * h)
                c, d = ((i + 1) * h, y, (k + 1) * h), (i * h, y, (k + 1) * h)
                tris += [(a, b, c), (a, c, d)] if (i + k) % 2 == 0 else [(a, b, d), (b, c, d)]
    d = os.path.join(ROOT, "bench", "scenes", "meshes")
    os.makedirs(d, exist_ok=True)
    write_ascii(os.path.join(d, "chute_sides.stl"), tris, name="chute_sides")  # LIGGGHTS reads ASCII STL


def silo_triangles(orifice, radius=0.06, height=0.3, segs=96, ring_height=0.02, ring_width=0.006):
    """A flat-bottomed cylindrical silo about the z axis: the wall from z = 0 to height as
    segs flat facets whose mid-lines lie at radius (vertices at radius / cos(pi/segs)), in
    rings ring_height tall, and the floor at z = 0, an annulus from the orifice out to the
    wall in rings about ring_width wide. The orifice polygon has the area of the circle of
    diameter orifice. Open at the top."""
    rv = radius / math.cos(math.pi / segs)
    ro = 0.5 * orifice * math.sqrt(2 * math.pi / (segs * math.sin(2 * math.pi / segs)))

    def ring(r, z):
        return [(r * math.cos(2 * math.pi * k / segs), r * math.sin(2 * math.pi * k / segs), z) for k in range(segs)]

    def band(lower, upper):
        out = []
        for k in range(segs):
            a, b = lower[k], lower[(k + 1) % segs]
            c, d = upper[(k + 1) % segs], upper[k]
            out += [(a, b, c), (a, c, d)]
        return out

    tris = []
    n_wall = max(1, round(height / ring_height))
    walls = [ring(rv, height * i / n_wall) for i in range(n_wall + 1)]
    for lower, upper in zip(walls, walls[1:]):
        tris += band(lower, upper)
    n_floor = max(1, round((rv - ro) / ring_width))
    floor = [ring(ro + (rv - ro) * i / n_floor, 0.0) for i in range(n_floor + 1)]
    for inner, outer in zip(floor, floor[1:]):
        tris += band(inner, outer)
    return tris


def silo():
    d = os.path.join(ROOT, "examples", "silo")
    os.makedirs(d, exist_ok=True)
    write_binary(os.path.join(d, "silo.stl"), silo_triangles(0.032), exact=False)


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else "all"
    if what == "silo" and len(sys.argv) == 4:
        write_ascii(sys.argv[2], silo_triangles(float(sys.argv[3])), name="silo")
        sys.exit(0)
    for name, f in (("verification", verification), ("bench", bench), ("hopper", hopper), ("silo", silo),
                    ("chute", chute)):
        if what in (name, "all"):
            f()
