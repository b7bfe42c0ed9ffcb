#!/usr/bin/python3
"""The table of bench/run_cfd_bench.sh from its runs file.

Each line of the runs file is one run:

    code problem particles cells simulated_s particle_steps loop_s cpu_s dp_Pa bed_height_m h99_m

(particle_steps: particles times DEM steps, DPMFoam's collision sub-cycles counted as steps).
Prints, per problem and code, the median loop time over the repetitions and each run, the
wall time per simulated second, particle-steps per second, cdm's speed against DPMFoam on
the same problem (DPMFoam's time / cdm's, in wall and in CPU time per simulated second),
the median CPU time (user + system) per simulated second, and the pressure drop and bed
height at the end of the median run.
"""
import statistics
import sys


def fail(msg):
    sys.exit(f"summarise_cfd.py: {msg}")


def read_runs(path):
    runs = {}
    with open(path) as f:
        for n, line in enumerate(f, 1):
            cols = line.split()
            if not cols:
                continue
            if len(cols) != 11:
                fail(f"{path}:{n}: {len(cols)} columns, expected 11: {line.strip()}")
            code, prob = cols[0], cols[1]
            try:
                vals = [float(v) for v in cols[2:]]
            except ValueError:
                fail(f"{path}:{n}: a column is not a number: {line.strip()}")
            if vals[2] <= 0 or vals[4] <= 0 or vals[5] <= 0:
                fail(f"{path}:{n}: simulated time, loop and CPU time must be > 0: {line.strip()}")
            runs.setdefault((prob, code), []).append(vals)
    if not runs:
        fail(f"{path}: no runs")
    return runs


def median_run(rs):
    """The run whose loop time is the median (the lower middle one for an even count)."""
    ordered = sorted(rs, key=lambda r: r[4])
    return ordered[(len(ordered) - 1) // 2]


def table(runs):
    rows = ["| problem | code | particles | cells | simulated s | loop wall s (median) | per run s | "
            "wall s per simulated s | CPU s per simulated s | particle-steps/s | cdm speed / DPMFoam, wall (CPU) | "
            "Δp Pa | bed height mm | h99 mm |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for (prob, code) in sorted(runs, key=lambda k: (k[0], k[1] != "cdm", k[1])):
        rs = runs[(prob, code)]
        m = median_run(rs)
        n, cells, sim, psteps, loop, cpu, dp, h, h99 = m
        loop_med = statistics.median(r[4] for r in rs)
        cpu_med = statistics.median(r[5] for r in rs)
        ratio = "-"
        if code == "cdm" and (prob, "dpmfoam") in runs:
            other = runs[(prob, "dpmfoam")]
            # Compare per simulated second: the two may have run for different times.
            def per_s(runs_, col):
                return statistics.median(r[col] / r[2] for r in runs_)
            ratio = f"{per_s(other, 4) / per_s(rs, 4):.2f}× ({per_s(other, 5) / per_s(rs, 5):.2f}×)"
        rows.append(f"| {prob} | {code} | {n:.0f} | {cells:.0f} | {sim:g} | {loop_med:.2f} | "
                    f"{', '.join(f'{r[4]:.2f}' for r in rs)} | {loop_med / sim:.4g} | {cpu_med / sim:.4g} | {psteps / loop:.3g} | {ratio} | "
                    f"{dp:.4g} | {1e3 * h:.4g} | {1e3 * h99:.4g} |")
    return "\n".join(rows)


def main():
    if len(sys.argv) != 2:
        fail("usage: summarise_cfd.py RUNS_FILE")
    print(table(read_runs(sys.argv[1])))


if __name__ == "__main__":
    main()
