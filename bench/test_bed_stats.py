#!/usr/bin/python3
"""bed_stats.py reads cdm's compressed binary VTK and its ascii VTK to the same numbers.

usage: test_bed_stats.py CDM BED_STATS_PY SOURCE_DIR WORK_DIR

Runs 120 steps of the Müller bed twice, frames every 1e-4 s, once in the default
compressed binary VTK and once in ascii, and runs `bed_stats.py cdm --series` on both:
the same times, pressure drops and bed heights (to 1e-9 relative: ascii carries 17
digits), a positive pressure drop after the start (the gas holds part of the bed), and
a bed height within the Müller bed's column. Then --window: the binary run's rows
averaged in windows of 2e-4 s and of 1e-4 s, each window's rows, mean and standard
deviation as computed here from the series (frames lie on the windows' edges). And
--probes: an OpenFOAM case holding only transportProperties and probes files whose
pressures are known (two layers of two probes; a restart's file, whose folder sorts
first as text, overriding the overlap) gives rho (mean low - mean high) per step and
its windowed means.
"""
import math
import os
import shutil
import subprocess
import sys


def lines(tool, *args):
    """bed_stats.py's output lines as {key: value}."""
    text = subprocess.run(["/usr/bin/python3", tool, *args], check=True, capture_output=True, text=True).stdout
    return [{k: float(v) for k, v in (kv.split("=") for kv in line.split())} for line in text.splitlines()]


def series(tool, out):
    return lines(tool, "cdm", out, "--axis", "y", "--series")


def close(a, b):
    """Equal to the 6 significant digits bed_stats.py prints."""
    return abs(a - b) <= 1e-5 * max(1e-3, abs(b))


def check_windows(tool, out, rows, width):
    got = lines(tool, "cdm", out, "--axis", "y", "--window", str(width))
    # Window k holds the rows with k width <= t < (k + 1) width (frames every 1e-4 s: some
    # lie on the edges, within round-off of them).
    groups = {}
    for r in rows:
        k = 0
        while r["t"] >= (k + 1) * width - 1e-12:
            k += 1
        groups.setdefault(k, []).append(r)
    if len(got) != len(groups):
        sys.exit(f"FAIL: {len(got)} windows, expected {len(groups)}")
    for w, k in zip(got, sorted(groups)):
        g = groups[k]
        n = len(g)
        dp = sum(r["dp"] for r in g) / n
        sd = math.sqrt(sum((r["dp"] - dp) ** 2 for r in g) / (n - 1)) if n > 1 else 0.0
        h = sum(r["bed_height"] for r in g) / n
        big = max(abs(r["dp"]) for r in g)  # the rows read here carry 6 digits: so does sd, of big
        if w["n"] != n or not close(w["t0"], k * width) or not close(w["dp"], dp) or abs(w["dp_sd"] - sd) > 2e-5 * big \
                or not close(w["bed_height"], h):
            sys.exit(f"FAIL: window {w}, expected t0={k * width} n={n} dp={dp} dp_sd={sd} bed_height={h}")
    if not any(close(r["t"], width) for r in rows):
        sys.exit(f"FAIL: no frame at the window edge t = {width} s, which the check needs")


def check_probes(tool, work):
    case = f"{work}/foam"
    os.makedirs(f"{case}/constant", exist_ok=True)
    with open(f"{case}/constant/transportProperties", "w") as f:
        f.write("continuousPhase air;\n\nrho.air         1.2;\n")
    head = "".join(f"# Probe {k} ({x} 0 {z})\n" for k, (x, z) in enumerate([(0, 0.0025), (1, 0.0025), (0, 0.35), (1, 0.35)]))
    head += "#       Probe 0 1 2 3\n#        Time\n"
    # p = 100 + t at the bottom (two probes, 1 either side), 5 at the top, at t = 8 ... 11 s;
    # a restart at t = 10 s (folder "10", which sorts before "8" as text) replaces the
    # first file's row at 10 s (which is 50 off).
    steps = [8.0, 9.0, 10.0, 11.0]
    def row(t, extra=0.0):
        return f"{t} {100 + t + 1 + extra} {100 + t - 1 + extra} 5 5\n"
    for start, ts in (("8", steps[:3]), ("10", steps[2:])):
        os.makedirs(f"{case}/postProcessing/pprobe/{start}", exist_ok=True)
        with open(f"{case}/postProcessing/pprobe/{start}/p", "w") as f:
            f.write(head + "".join(row(t, 50.0 if start == "8" and t == 10.0 else 0.0) for t in ts))
    expect = [(t, 1.2 * (95 + t)) for t in steps]
    got = lines(tool, "openfoam", case, "--probes", "--series")
    if [r["t"] for r in got] != steps or not all(close(r["dp"], e) for r, (_, e) in zip(got, expect)):
        sys.exit(f"FAIL: probes {got}, expected {expect}")
    win = lines(tool, "openfoam", case, "--probes", "--window", "2")
    want = [(8.0, 2, 1.2 * 103.5), (10.0, 2, 1.2 * 105.5)]
    if len(win) != len(want) or not all(close(w["t0"], t0) and w["n"] == n and close(w["dp"], dp)
                                        for w, (t0, n, dp) in zip(win, want)):
        sys.exit(f"FAIL: probe windows {win}, expected (t0, n, dp) {want}")
    # Steps on the windows' edges as OpenFOAM names them: 0.03 / 0.01 rounds below 3.
    with open(f"{case}/postProcessing/pprobe/8/p", "w") as f:
        f.write(head + "".join(row(t) for t in (0.01, 0.02, 0.03, 0.04)))
    shutil.rmtree(f"{case}/postProcessing/pprobe/10")
    win = lines(tool, "openfoam", case, "--probes", "--window", "0.01")
    if [(round(w["t0"], 9), w["n"]) for w in win] != [(0.01, 1), (0.02, 1), (0.03, 1), (0.04, 1)]:
        sys.exit(f"FAIL: probe windows {win}, expected one step in each of [0.01, 0.02) ... [0.04, 0.05)")


def main():
    cdm, tool, src, work = sys.argv[1:5]
    shutil.rmtree(work, ignore_errors=True)
    scene = f"{src}/bench/scenes/mueller_bubbling_bed.toml"
    runs = {}
    for fmt in ("binary", "ascii"):
        subprocess.run([cdm, "run", scene, "-q", "-j", "1", "--max-steps", "120", "--set", "output.interval=1.0e-4",
                        "--set", "output.particles=true", "--set", f'output.vtk_format="{fmt}"',
                        "-o", f"{work}/{fmt}"], check=True, capture_output=True, text=True)
        runs[fmt] = series(tool, f"{work}/{fmt}")
    b, a = runs["binary"], runs["ascii"]
    if len(b) < 3 or len(b) != len(a):
        sys.exit(f"FAIL: {len(b)} binary rows, {len(a)} ascii rows (expected the same, at least 3)")
    for rb, ra in zip(b, a):
        for k in ("t", "dp", "bed_height", "h99"):
            if abs(rb[k] - ra[k]) > 1e-9 * max(1.0, abs(ra[k])):
                sys.exit(f"FAIL: at t = {ra['t']}, {k} binary {rb[k]!r} against ascii {ra[k]!r}")
    last = b[-1]
    if not last["dp"] > 0.0 or not 0.0 < last["bed_height"] <= 0.12:
        sys.exit(f"FAIL: implausible last row {last}")
    for width in (2e-4, 1e-4):  # 3e-4 / 1e-4 rounds below 3: a frame on an edge
        check_windows(tool, f"{work}/binary", b, width)
    check_probes(tool, work)
    print(f"ok: {len(b)} frames the same from binary and ascii VTK; last dp = {last['dp']:.6g} Pa, "
          f"bed height {last['bed_height']:.6g} m; windows and OpenFOAM probes as computed here")


if __name__ == "__main__":
    main()
