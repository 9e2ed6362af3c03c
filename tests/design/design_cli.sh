#!/usr/bin/env bash
# `thermnet check` and `thermnet design` on a two-node network (a heater film on a plate losing
# heat to falling air; the thermostat senses the plate): the design meets every requirement when
# re-simulated by thermnet (`check` on the written model) and by an independent SciPy simulation;
# an impossible power budget is reported as infeasible naming the violated requirement.
# Usage: design_cli.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

cat >plate.tnet <<'TNET'
model plate
boundary air T = pwl(0: 10, 500: -20)
node plate C = 2000 [J/K]
node film C = 50 [J/K] "heater film"
contact bond film plate h = 1000 A = 0.002
conductance leak plate air G = 0.5
param P = 10 [W] range 1 .. 60 "heater power"
thermostat th film P = P on = 15 off = 18 sense = plate
require band "plate" 14 .. 22 [degC] from 600 [s] "plate held"
require margin "th" min 50 [%] from 600 [s] "power margin"
require power "th" max 100 [W]
case run { duration = 3000 ; output = 2 ; initial = 20 }
TNET

# check: the declared 10 W cannot hold the plate (its steady leak at -20 degC is about 18 W)
run check plate.tnet --json check.json
check "check exits 1 when a requirement is violated" [ "$rc" -eq 1 ]
check "check names the violated band with its location" grep -q '^plate.tnet:9:1: requirement VIOLATED: require band "plate"' out.txt
check "check reports the worst node and the amount in degC" grep -q 'worst plate = .* degC at t = .*violated by' out.txt
check "check --json lists every requirement" python3 -c '
import json; j = json.load(open("check.json")); assert not j["met"] and len(j["requirements"]) == 3
b = j["requirements"][0]; assert b["kind"] == "band" and b["line"] == 9 and not b["met"] and b["slack"] < 0'

# check --set: 30 W holds the plate with a 50 % margin over its ~18 W need; a stronger leak does not
run check plate.tnet --set P=30
check "check --set P=30: every requirement met" [ "$rc" -eq 0 ]
run check plate.tnet --set P=30 --set leak.G=1
check "check --set leak.G=1 (twice the leak): the band is violated again" [ "$rc" -eq 1 ]
check "... named" grep -q 'requirement VIOLATED: require band "plate"' out.txt

# design: the least installed power meeting the band and the 50 % margin
run design plate.tnet --objective power --seed 3 -o designed.tnet --json design.json --plot design.svg
check "design exits 0 when the requirements can be met" [ "$rc" -eq 0 ]
check "design writes the designed model" grep -q '^param P = .* \[W\] range 1 .. 60' designed.tnet
check "design writes a plot with the band" grep -q 'band plate' design.svg
P=$(python3 -c 'import json; print(json.load(open("design.json"))["params"]["P"])')
check "the least power with a 50 % margin over the ~17.5-18.5 W leak: 1.5 x leak (25.5 .. 28 W)" \
  python3 -c "import sys; sys.exit(0 if 25.5 < $P < 28 else 1)"
run check designed.tnet
check "the written model meets every requirement when simulated again" [ "$rc" -eq 0 ]
check "... and check prints each margin" grep -q 'requirement met: require margin' out.txt
check "an independent SciPy simulation of the design meets the band and margin" \
  /usr/bin/python3 "$HERE/plate_scipy.py" "$P"

# the same seed gives the same design whatever the thread count
run design plate.tnet --objective power --seed 3 --threads 1 --json design1.json
check "same seed, one thread: same design" python3 -c '
import json; a = json.load(open("design.json"))["params"]; b = json.load(open("design1.json"))["params"]
assert a == b, (a, b)'

# an impossible budget: 20 W cannot give a 50 % margin over an 18 W need
sed 's/require power "th" max 100 \[W\]/require power "th" max 20 [W]/' plate.tnet >tight.tnet
run design tight.tnet --objective power -o tight_out.tnet
check "design exits 1 when the budget makes the requirements impossible" [ "$rc" -eq 1 ]
check "... says the requirements cannot be met" grep -q 'cannot be met within the ranges' err.txt
check "... names a violated requirement with its location and amount" \
  grep -Eq 'tight.tnet:(9|10|11):1: requirement VIOLATED: require (band|margin|power).*violated by' err.txt
check "... and writes no model" [ ! -e tight_out.tnet ]

# simulate reports the requirements on standard error, the CSV is unchanged
run simulate plate.tnet -o run.csv
check "simulate reports requirements on stderr" grep -q 'requirement VIOLATED: require band' err.txt
check "simulate keeps exit 0 (check is the gate)" [ "$rc" -eq 0 ]

finish
