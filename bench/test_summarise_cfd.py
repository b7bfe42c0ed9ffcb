#!/usr/bin/python3
"""bench/summarise_cfd.py on a runs file whose ratios are known by construction.

    bench/test_summarise_cfd.py SUMMARISE_CFD
"""
import sys

from table_checks import check, failures, table_row
from table_checks import run as run_script

summarise = sys.argv[1]


def run(text):
    return run_script(summarise, text)[0]


def row(out, prob, code):
    return table_row(out, prob, code)


# cdm: medians 6 s wall, 5 s CPU over 0.0002 s (3e4 and 2.5e4 s per simulated s); DPMFoam
# ran twice as long (0.0004 s) in 30 s wall, 20 s CPU (7.5e4 and 5e4): cdm 2.5x (2x).
runs = """\
cdm goldschmidt 24750 5400 0.0002 742500 7.0 6.0 700 0.290 0.295
cdm goldschmidt 24750 5400 0.0002 742500 5.0 4.0 500 0.280 0.285
cdm goldschmidt 24750 5400 0.0002 742500 6.0 5.0 600 0.270 0.275
dpmfoam goldschmidt 24750 5400 0.0004 990000 30 20 1500 0.297 0.29675
cdm mueller 9240 1800 0.001 3141600 10 9 43.7 0.062 0.0618
"""
r = run(runs)
check(f"exit status 0, got {r.returncode}: {r.stderr}", r.returncode == 0)
cdm = row(r.stdout, "goldschmidt", "cdm")
dpm = row(r.stdout, "goldschmidt", "dpmfoam")
mue = row(r.stdout, "mueller", "cdm")
check("a goldschmidt cdm row", cdm is not None)
check("a goldschmidt dpmfoam row", dpm is not None)
check("a mueller cdm row", mue is not None)
if cdm and dpm and mue:
    check(f"cdm median loop 6.00, got {cdm[5]}", cdm[5] == "6.00")
    check(f"cdm runs listed in order, got {cdm[6]}", cdm[6] == "7.00, 5.00, 6.00")
    check(f"cdm wall per simulated s 3e+04, got {cdm[7]}", cdm[7] == "3e+04")
    check(f"cdm CPU per simulated s 2.5e+04, got {cdm[8]}", cdm[8] == "2.5e+04")
    check(f"cdm particle-steps/s of the median run 742500/6, got {cdm[9]}", cdm[9] == "1.24e+05")
    check(f"cdm against DPMFoam 2.50x (2.00x), got {cdm[10]}", cdm[10] == "2.50× (2.00×)")
    check(f"the median run's dp and heights, got {cdm[11:14]}", cdm[11:14] == ["600", "270", "275"])
    check(f"DPMFoam has no ratio, got {dpm[10]}", dpm[10] == "-")
    check(f"a problem without DPMFoam has no ratio, got {mue[10]}", mue[10] == "-")

for bad, what in [("cdm goldschmidt 1 2 3\n", "too few columns"),
                  ("cdm goldschmidt 24750 5400 0.0002 742500 x 6 700 0.29 0.3\n", "not a number"),
                  ("cdm goldschmidt 24750 5400 0 742500 7 6 700 0.29 0.3\n", "zero simulated time"),
                  ("", "no runs")]:
    r = run(bad)
    check(f"{what}: refused with status != 0 and a message", r.returncode != 0 and "summarise_cfd.py" in r.stderr)

if failures:
    print("FAILED:\n  " + "\n  ".join(failures))
    sys.exit(1)
print("summarise_cfd.py: all checks passed")
