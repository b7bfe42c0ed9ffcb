#!/usr/bin/env bash
# The examples run as their READMEs say (shortened to a few hundred steps), and the silo's
# Beverloo fit (examples/silo/beverloo.py) gives back C and k from rates that follow the
# law exactly, and a discharge rate from a table of known slope.
set -u
cdm="$1" src="$2" work="$3"
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/common.sh"
PY=/usr/bin/python3

for ex in hopper/scene.toml rotating_drum/drum.toml bed_fed_from_above/scene.toml silo/silo.toml; do
  name=$(dirname "$ex")
  "$cdm" run "$src/examples/$ex" -q -o "$work/$name" --max-steps 200 > /dev/null || fail "example $ex"
done
# The silo's beads start inside its wall (a cylinder region of radius 57.5 mm, wall at 60 mm).
$PY - "$work/silo/outlets.dat" <<'PYEOF' || fail "silo example: the population table"
import sys
rows = [l.split() for l in open(sys.argv[1]) if not l.startswith("#")]
assert int(rows[-1][5]) == 24000, rows[-1]
PYEOF
"$cdm" run "$src/examples/silo/silo.toml" -q -o "$work/silo0" --max-steps 1 --set output.particles=true > /dev/null ||
  fail "silo example with particles.dat"
$PY - "$work/silo0/particles.dat" <<'PYEOF' || fail "silo example: beads outside the cylinder region"
import math, sys
n = 0
for l in open(sys.argv[1]):
    if l.startswith("#"):
        continue
    c = l.split()
    if float(c[0]) != 0.0:
        break
    x, y, z = float(c[2]), float(c[3]), float(c[4])
    assert math.hypot(x, y) <= 0.0575 * (1 + 1e-12) and 0.003 <= z <= 0.263, (x, y, z)
    n += 1
assert n == 24000, n
PYEOF

# Beverloo's law recovered from exact rates (C = 0.58, k = 1.4, d = 4 mm, rho_b = 1500).
pts=$($PY -c "
import math
print(' '.join('%r:%r' % (D, 0.58 * 1500 * math.sqrt(9.81) * (D - 1.4 * 0.004) ** 2.5) for D in (0.02, 0.032, 0.048)))")
fit=$($PY "$src/examples/silo/beverloo.py" fit $pts) || fail "beverloo.py fit"
echo "$fit" | grep -q "C = 0.5800, k = 1.400" || fail "beverloo.py fit: $fit"
# A discharge table of 0.25 kg/s from 0.2 s on: the rate and its halves.
$PY -c "
print('# t inserted inserted_mass below below_mass particles particle_mass')
for k in range(101):
    t = 0.01 * k
    print(t, 0, 0.0, 0, 0.25 * max(t - 0.2, 0.0), 0, 0.0)" > "$work/outlets.dat"
rate=$($PY "$src/examples/silo/beverloo.py" rate "$work/outlets.dat" --from 0.3) || fail "beverloo.py rate"
echo "$rate" | grep -q "W = 0.25 kg/s (halves 0.25, 0.25" || fail "beverloo.py rate: $rate"
echo "examples: all run; Beverloo fit and rate recovered"
