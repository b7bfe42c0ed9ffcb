#!/usr/bin/env python3
"""The mass balance of a run with insertions and outlets, over the whole time series
(tests/cli/population.sh). At every row of OUTDIR/outlets.dat:
  - particles = particles at t=0 + inserted - removed by all outlets (exactly);
  - particle_mass = mass at t=0 + inserted_mass - removed mass, to 1e-12 of the mass
    (the three sums add the same masses in other orders);
  - particles and particle_mass equal the rows of particles.dat at that time and the
    mass of their radii (rho pi d^3 / 6, density given), to 1e-12;
  - inserted = min(total, rate * k * INTERVAL) at and after insertion event k (events
    every INTERVAL from START; rate * INTERVAL a whole number): the rate the scene asks
    for, at every sample, the last one (not on an event) too.
Usage: check_population.py OUTDIR DENSITY RATE INTERVAL TOTAL [START]"""
import math
import sys
from collections import defaultdict

out, density, rate, interval, total = sys.argv[1], *map(float, sys.argv[2:6])
start = float(sys.argv[6]) if len(sys.argv) > 6 else 0.0


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


rows = []
with open(out + "/outlets.dat") as f:
    for line in f:
        if line.startswith("#"):
            header = line[1:].split()
            continue
        rows.append([float(v) for v in line.split()])
if len(rows) < 3:
    fail("outlets.dat has %d rows" % len(rows))
outlets = (len(header) - 5) // 2
samples = defaultdict(lambda: [0, 0.0])
with open(out + "/particles.dat") as f:
    for line in f:
        if line.startswith("#"):
            continue
        v = line.split()
        d = 2.0 * float(v[-2])
        s = samples[v[0]]
        s[0] += 1
        s[1] += density * math.pi * d * d * d / 6.0
n0, m0 = int(rows[0][-2]), rows[0][-1]
for r in rows:
    t, ins, ins_m = r[0], int(r[1]), r[2]
    rem = sum(int(r[3 + 2 * o]) for o in range(outlets))
    rem_m = sum(r[4 + 2 * o] for o in range(outlets))
    n, m = int(r[-2]), r[-1]
    if n != n0 + ins - rem:
        fail("t = %r: %d particles, expected %d + %d - %d" % (t, n, n0, ins, rem))
    if abs(m - (m0 + ins_m - rem_m)) > 1e-12 * max(m, m0):
        fail("t = %r: mass %r, expected %r" % (t, m, m0 + ins_m - rem_m))
    key = "%.16e" % t
    got = samples.get(key, [0, 0.0])
    if got[0] != n or abs(got[1] - m) > 1e-12 * max(m, 1e-300):
        fail("t = %r: particles.dat has %d particles of %r kg, outlets.dat %d of %r" % (t, got[0], got[1], n, m))
    want = min(total, rate * math.floor((t - start) / interval + 1e-9) * interval) if t >= start else 0
    if ins != round(want):
        fail("t = %r: %d inserted, expected %d (rate %r/s)" % (t, ins, want, rate))
print("population: %d rows balanced; %d inserted, %d removed, %d left" % (len(rows), ins, rem, n))
