#!/usr/bin/python3
"""bed_stats.py reads cdm's compressed binary VTK and its ascii VTK to the same numbers.

usage: test_bed_stats.py CDM BED_STATS_PY SOURCE_DIR WORK_DIR

Runs 120 steps of the Müller bed twice, frames every 1e-4 s, once in the default
compressed binary VTK and once in ascii, and runs `bed_stats.py cdm --series` on both:
the same times, pressure drops and bed heights (to 1e-9 relative: ascii carries 17
digits), a positive pressure drop after the start (the gas holds part of the bed), and
a bed height within the Müller bed's column.
"""
import shutil
import subprocess
import sys


def series(tool, out):
    text = subprocess.run(["/usr/bin/python3", tool, "cdm", out, "--axis", "y", "--series"],
                          check=True, capture_output=True, text=True).stdout
    return [{k: float(v) for k, v in (kv.split("=") for kv in line.split())} for line in text.splitlines()]


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
    print(f"ok: {len(b)} frames the same from binary and ascii VTK; last dp = {last['dp']:.6g} Pa, "
          f"bed height {last['bed_height']:.6g} m")


if __name__ == "__main__":
    main()
