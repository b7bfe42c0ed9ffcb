#!/usr/bin/python3
"""bench/summarise.py on a runs file whose ratios are known by construction.

    bench/test_summarise.py SUMMARISE
"""
import sys

from table_checks import check, failures, table_row
from table_checks import run as run_script

summarise = sys.argv[1]


def run(text):
    return run_script(summarise, text)


def row(out, prob, code, cores):
    return table_row(out, prob, code, cores)


# Three repetitions each; the medians are 10 (cdm), 5 (cdm2), 30 (lammps), 15 (lammps2),
# 40 (liggghts) on settle1e6 (N 1e6, 1000 steps); settle1e4 in 4 segments, settle1e4early.
runs = """\
cdm settle1e6 1000000 1000 9 480000 9
cdm settle1e6 1000000 1000 10 470000 10
cdm settle1e6 1000000 1000 12 490000 12
cdm2 settle1e6 1000000 1000 5 500000 5
cdm2 settle1e6 1000000 1000 4 500000 4
cdm2 settle1e6 1000000 1000 6 500000 6
lammps settle1e6 1000000 1000 30 570000 30
lammps settle1e6 1000000 1000 31 570000 31
lammps settle1e6 1000000 1000 29 570000 29
lammps2 settle1e6 1000000 1000 15 0 15
lammps2 settle1e6 1000000 1000 15 0 15
lammps2 settle1e6 1000000 1000 16 0 16
liggghts settle1e6 1000000 1000 40 600000 40
liggghts settle1e6 1000000 1000 40 600000 40
liggghts settle1e6 1000000 1000 41 600000 41

cdm settle1e4 10000 40000 10 1000 1,2,3,4
cdm settle1e4 10000 40000 10 1000 1,2,3,4
cdm settle1e4 10000 40000 10 1000 1,2,3,4
lammps settle1e4 10000 40000 30 4000 2,6,10,12
lammps settle1e4 10000 40000 30 4000 2,6,10,12
lammps settle1e4 10000 40000 30 4000 2,6,10,12
cdm settle1e4early 10000 1000 0.05 1000 0.05
cdm settle1e4early 10000 1000 0.05 1000 0.05
cdm settle1e4early 10000 1000 0.05 1000 0.05
lammps settle1e4early 10000 1000 0.2 4000 0.2
lammps settle1e4early 10000 1000 0.2 4000 0.2
lammps settle1e4early 10000 1000 0.2 4000 0.2
"""
res, _ = run(runs)
out = res.stdout
check(f"exit 0 (got {res.returncode}: {res.stderr})", res.returncode == 0)
cdm = row(out, "settle1e6", "cdm", 1)
check(f"cdm 1 core: median 10.00, each run listed, 1e5 particle-steps/s, 480 B per particle: {cdm}",
      cdm is not None and cdm[5] == "10.00" and cdm[6] == "9.00, 10.00, 12.00" and cdm[7] == "1e+08"
      and cdm[8] == "492" and cdm[9] == "-" and cdm[10] == "-")
cdm2 = row(out, "settle1e6", "cdm", 2)
check(f"cdm 2 cores: 2.00× one core, 1e8 per core: {cdm2}",
      cdm2 is not None and cdm2[7] == "1e+08" and cdm2[10] == "2.00×")
lmp = row(out, "settle1e6", "lammps", 1)
check(f"lammps 1 core: cdm 3.00× faster: {lmp}", lmp is not None and lmp[9] == "3.00×" and lmp[10] == "-")
lmp2 = row(out, "settle1e6", "lammps", 2)
check(f"lammps 2 ranks: against cdm's 2 threads (3.00×), 2.00× its one rank, memory not measured: {lmp2}",
      lmp2 is not None and lmp2[9] == "3.00×" and lmp2[10] == "2.00×" and lmp2[8] == "-")
lig = row(out, "settle1e6", "liggghts", 1)
check(f"liggghts 1 core 4.00×: {lig}", lig is not None and lig[9] == "4.00×")
check("no liggghts 2-core row (not run)", row(out, "settle1e6", "liggghts", 2) is None)
early = row(out, "settle1e4early", "cdm", 1)
check(f"short loop times get three decimals: {early}", early is not None and early[5] == "0.050")
seg = [line for line in out.splitlines() if line.startswith("| lammps | 1 | 2.00")]
check(f"settle1e4's segments, lammps against cdm per segment: {seg}",
      seg == ["| lammps | 1 | 2.00 (2.00) | 6.00 (3.00) | 10.00 (3.33) | 12.00 (3.00) |"])
# Cost per particle-step: cdm 10 ns at 1e6, 5 ns on the first 1000 steps at 1e4 (2.00×),
# 10 ns on settle1e4's first segment (1.00×); lammps 30, 20 (1.50×), 20 (1.50×).
cost = [line for line in out.splitlines() if line.startswith("| cdm | 5.00 |")]
check(f"cdm's cost per particle-step against N: {cost}",
      cost == ["| cdm | 5.00 | 10.00 | 10.00 | 2.00× | 1.00× |"])
cost = [line for line in out.splitlines() if line.startswith("| lammps | 20.00 |")]
check(f"lammps's cost per particle-step against N: {cost}",
      cost == ["| lammps | 20.00 | 20.00 | 30.00 | 1.50× | 1.50× |"])

# A malformed line: refused with the file and line named, nothing on stdout.
for bad, why in (("cdm settle1e6 1000000 1000 ten 480000 10\n", "ten"),
                 ("cmd settle1e6 1000000 1000 10 480000 10\n", "unknown code"),
                 ("cdm settle1e6 1000000 1000 10 480000\n", "expected"),
                 ("cdm settle1e6 0 1000 10 480000 10\n", "positive")):
    res, name = run(runs + bad)
    check(f"bad line {bad.strip()!r}: exit non-zero, message names {name}:29 and {why!r}, no output "
          f"(got {res.returncode}, {res.stderr!r}, {len(res.stdout)} chars)",
          res.returncode != 0 and f"{name}:29:" in res.stderr and why in res.stderr and res.stdout == "")
res, name = run("")
check("an empty runs file is refused", res.returncode != 0 and "no runs" in res.stderr and res.stdout == "")

if failures:
    print("FAILED:\n  " + "\n  ".join(failures))
    print(out)
    sys.exit(1)
print("bench/summarise.py: all checks passed")
