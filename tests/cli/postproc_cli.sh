#!/usr/bin/env bash
# The post-processing reports of `thermnet simulate` against analytic values: heat flows of a
# series slab (steady listing and transient CSV), the energy balance of a transient, a thermostat's
# analytic duty cycle, the per-node summary with the time outside a band, --nodes globs selecting
# CSV columns, --unit K, bad options; sensitivity of set points in degC; kinds' limits. Usage: postproc_cli.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

# Series slab hot(100) - g1 (2 W/K) - a - g2 (1 W/K) - b - r3 (0.5 K/W) - cold(0): 0.5 W/K overall,
# 50 W through every link at steady state, a = 75 degC, b = 25 degC.
cat >slab.tnet <<'EOF'
model slab
boundary hot T = 100
boundary cold T = 0
node a C = 100
node b C = 300
conductance g1 hot a G = 2
conductance g2 a b G = 1
resistor r3 b cold R = 0.5
heater q a P = step(0: 0, 500: 40)
case c { duration = 2000 ; output = 5 ; initial = 0 }
EOF
# box loses 1 W/K to 0 degC; 30 W while on, on at 17 degC, off at 20 degC, from 17 degC. Each cycle
# heats 17 -> 20 in 1000 ln(13/10) s and cools back in 1000 ln(20/17) s; 100 cycles in the run.
cat >thermo.tnet <<'EOF'
model thermo
boundary amb T = 0
node box C = 1000 [J/K]
conductance loss box amb G = 1
thermostat th box P = 30 [W] on = 17 off = 20
case c { duration = 42488.196 ; output = 5 ; initial = 17 }
EOF

run simulate slab.tnet --steady --flows listing.txt -o steady.csv
check "steady flows: exit 0" [ "$rc" = 0 ]
check "steady listing: 50 W through each link, balances closed" python3 - <<'EOF'
import re
text = open("listing.txt").read()
flows = {m[0] + "@" + m[1]: float(m[2]) for m in re.findall(
    r"^  (\w+)\s+from (\w+)\s+(-?[\d.]+)$", text, re.M)}
assert abs(flows["g1@hot"] - 50) < 1e-6 and abs(flows["g2@a"] - 50) < 1e-6, flows
assert abs(flows["r3@cold"] + 50) < 1e-6 and abs(flows["g2@b"] + 50) < 1e-6, flows
res = [float(x) for x in re.findall(r"balance residual\s+(\S+)", text)]
assert len(res) == 2 and all(abs(r) < 1e-9 for r in res), res
EOF

run simulate slab.tnet --flows flows.csv --energy energy.txt -o temps.csv --rtol 1e-8 --atol 1e-8
check "transient flows and energy: exit 0" [ "$rc" = 0 ]
check "flow CSV: the node balances give C dT/dt, the energy report closes" python3 - <<'EOF'
import csv, re
f = list(csv.DictReader(open("flows.csv")))
T = list(csv.DictReader(open("temps.csv")))
assert list(f[0].keys()) == ["time", "g1", "g2", "r3", "q@a"], f[0].keys()
# Every flow equals its conductance times the temperature difference at that row.
for rf, rt in zip(f, T):
    a, b = float(rt["a"]), float(rt["b"])
    assert abs(float(rf["g1"]) - 2 * (100 - a)) < 1e-6
    assert abs(float(rf["g2"]) - (a - b)) < 1e-6
    assert abs(float(rf["r3"]) - 2 * b) < 1e-6
# The end state is steady (a from the 40 W heater): 50 W + part of 40 W, equal flows g2 = r3.
last = f[-1]
assert abs(float(last["g2"]) - float(last["r3"])) < 1e-3, last
text = open("energy.txt").read()
m = re.search(r"total: stored (\S+) = supplied (\S+) - lost to boundaries (\S+); residual (\S+) J", text)
stored, supplied, lost, resid = map(float, m.groups())
# Stored: C (T_end - T_start), computed from the temperatures; the integrals close on it.
C_a, C_b = 100, 300
stored_T = C_a * float(T[-1]["a"]) + C_b * float(T[-1]["b"])
assert abs(stored - stored_T) < 1e-3 * stored_T, (stored, stored_T)
assert abs(supplied - 40 * 1500) < 1e-3, supplied
assert abs(resid) < 1e-5 * supplied, resid
EOF

run simulate thermo.tnet --energy duty.txt --summary summary.csv --band 17.5..19.5 --nodes 'b*' -o box.csv
check "thermostat: exit 0" [ "$rc" = 0 ]
check "thermostat: analytic duty, switch count, energy; time outside the band" python3 - <<'EOF'
import csv, math, re
on, off = 1000 * math.log(13 / 10), 1000 * math.log(20 / 17)
text = open("duty.txt").read()
energy, on_time, duty, switches = re.search(r"^th\s+(\S+)\s+(\S+)\s+(\S+)\s+(\d+)$", text, re.M).groups()
assert abs(float(on_time) - 100 * on) < 1e-4 * 100 * on, on_time
assert abs(float(duty) - on / (on + off)) < 1e-4, duty
assert int(switches) in (199, 200), switches
assert abs(float(energy) - 30 * 100 * on) < 1e-4 * 30 * 100 * on, energy
resid = float(re.search(r"residual (\S+) J", text).group(1))
assert abs(resid) < 1e-4 * float(energy), resid
# Outside 17.5 .. 19.5 per cycle: 17 -> 17.5 and 19.5 -> 20 heating, 20 -> 19.5 and 17.5 -> 17 cooling.
out = 1000 * (math.log(13 / 12.5) + math.log(10.5 / 10) + math.log(20 / 19.5) + math.log(17.5 / 17))
rows = list(csv.DictReader(open("summary.csv")))
assert [r["node"] for r in rows] == ["box"], rows
r = rows[0]
assert abs(float(r["time_outside"]) - 100 * out) < 0.002 * 100 * out, (r, 100 * out)
assert abs(float(r["max"]) - 20) < 0.01 and abs(float(r["min"]) - 17) < 0.01, r
assert 17 < float(r["mean"]) < 20
assert open("box.csv").readline().strip() == "time,box"
EOF

run simulate slab.tnet --steady --unit K --nodes 'a,b'
check "--unit K: kelvin columns" python3 -c "
import csv,sys; r=list(csv.DictReader(open('out.txt')))[0]; assert abs(float(r['a'])-348.15)<1e-6, r"

run simulate slab.tnet --steady --flows fsel.txt --elements 'g*'
check "--elements: only the selected links are listed" sh -c '! grep -q "^  r3" fsel.txt && grep -q "^  g2" fsel.txt'

run simulate slab.tnet --nodes 'zz*'
check "--nodes glob matching nothing: usage error" [ "$rc" = 2 ]
check "... naming the option" grep -q -- "--nodes: the model has no node or boundary 'zz\*'" err.txt
run simulate slab.tnet --summary s.csv --band 25..15
check "--band upside down: usage error" [ "$rc" = 2 ]
run simulate slab.tnet --steady --energy e.txt
check "--energy with --steady: usage error" [ "$rc" = 2 ]
check "... and nothing written" [ ! -e e.txt ]

# Set points stay in degC and are scaled per kelvin: th.on is 17 degC with scale 1 K, not 290 K.
run sensitivity thermo.tnet --elements --json sens.json
check "sensitivity: exit 0" [ "$rc" = 0 ]
check "sensitivity: thermostat set points in degC, per kelvin" python3 - <<'EOF'
import json
f = {x["name"]: x for x in json.load(open("sens.json"))["factors"]}
assert f["th.on"]["value"] == 17 and f["th.on"]["unit"] == "degC" and f["th.on"]["scale"] == 1, f["th.on"]
assert f["th.off"]["value"] == 20 and f["th.P"]["scale"] == 30, f
EOF
check "sensitivity table: 17 degC" grep -q "th.on  *17 degC" out.txt
run kinds thermostat
check "kinds: the real limit of a set point" grep -q "on .*above absolute zero (> -273.15 degC)" out.txt

run simulate slab.tnet --json run.json --nodes 'a,b' --elements g2 --unit K -o /dev/null
check "--json: exit 0" [ "$rc" = 0 ]
check "--json: nodes, times, temperatures (K) and flows that agree with them" python3 - <<'EOF'
import json
d = json.load(open("run.json"))
assert d["nodes"] == ["a", "b"] and d["flow_columns"] == ["g2"] and d["unit"] == "K", d["nodes"]
assert len(d["times"]) == len(d["temperatures"]) == len(d["flows"]) == 401
for T, q in zip(d["temperatures"], d["flows"]):
    assert abs(q[0] - (T[0] - T[1])) < 1e-9, (T, q)
assert abs(d["temperatures"][0][0] - 273.15) < 1e-9
EOF

# Sweeps: the same numbers as separate --set runs, whatever the thread count.
cat >swept.tnet <<'EOF'
model swept
param G = 1 [W/K] range 0.5 .. 2
param T_on = 17 [degC]
boundary amb T = 0
node box C = 1000 [J/K]
conductance loss box amb G = G
thermostat th box P = 30 [W] on = T_on off = 20
case c { duration = 5000 ; output = 10 ; initial = 17 }
EOF
run sweep swept.tnet --param G=0.5..2:4 --param T_on=16,17 --nodes box --band 17.5..19.5 --threads 2 -o sweep2.csv --plot sweep.svg
check "sweep: exit 0" [ "$rc" = 0 ]
check "sweep: an SVG plot" grep -q "<svg" sweep.svg
run sweep swept.tnet --param G=0.5..2:4 --param T_on=16,17 --nodes box --band 17.5..19.5 --threads 1 -o sweep1.csv
check "sweep: the same table with 1 and 2 threads" cmp sweep1.csv sweep2.csv
for g in 0.5 1.5; do
  "$TN" simulate swept.tnet --set G=$g --set T_on=16 --summary set_$g.csv --band 17.5..19.5 --nodes box -o /dev/null
done
check "sweep: rows equal separate --set runs (degC param set in degC)" python3 - <<'EOF'
import csv
rows = list(csv.DictReader(open("sweep2.csv")))
assert [(r["G"], r["T_on"]) for r in rows][:4] == [("0.5", "16"), ("0.5", "17"), ("1", "16"), ("1", "17")], rows
for g in ("0.5", "1.5"):
    single = list(csv.DictReader(open(f"set_{g}.csv")))[0]
    row = next(r for r in rows if r["G"] == g and r["T_on"] == "16")
    for a, b in (("box_min", "min"), ("box_max", "max"), ("box_mean", "mean"), ("box_time_outside", "time_outside")):
        assert abs(float(row[a]) - float(single[b])) < 1e-9, (g, a, row[a], single[b])
EOF
run sweep swept.tnet --param G=1..2:1
check "sweep: N below 2 is a usage error" [ "$rc" = 2 ]
run sweep swept.tnet --param Gx=1,2
check "sweep: an unknown param is named, with a suggestion" grep -q "no param 'Gx'; did you mean 'G'" err.txt
run simulate swept.tnet --set 'G=2 [mm]'
check "--set with the wrong dimension: usage error" [ "$rc" = 2 ]
check "... saying so" grep -q "param 'G' is in W/K, not m" err.txt

# ------------------------------------------------ every CSV quotes generated names (issue 31)
# A 2 x 2 grid of nodes: each output's header and rows must have as many fields for a CSV reader.
cat >grid.tnet <<'EOF'
model grid
boundary amb T = 0
for i in 1 .. 2, j in 1 .. 2 {
  node p[i, j] C = 100 T0 = 20
  conductance g[i, j] p[i, j] amb G = 1
}
case c { duration = 100 ; output = 10 }
EOF
run simulate grid.tnet -o grid.csv --summary summary.csv --flows flows.csv
check "grid: simulate with --summary and --flows exits 0" [ "$rc" = 0 ]
run sweep grid.tnet --param 'g[1,2].G=1,2' -o sweep.csv
check "grid: sweep exits 0" [ "$rc" = 0 ]
run simulate grid.tnet -o data.csv
run estimate grid.tnet data.csv --case c --measured 'p[1,1],p[1,2]' -o est.csv
check "grid: estimate --measured 'p[1,1],p[1,2]' takes two names" [ "$rc" = 0 ]
check "every CSV parses with as many fields per row as its header, names intact" python3 - <<'EOF'
import csv
for name, first in [("grid.csv", ["time", "amb", "p[1,1]", "p[1,2]", "p[2,1]", "p[2,2]"]),
                    ("summary.csv", ["node", "min"]), ("flows.csv", ["time", "g[1,1]"]),
                    ("sweep.csv", ["g[1,2].G", "amb_min"]), ("est.csv", ["time"])]:
    rows = list(csv.reader(open(name)))
    assert all(len(r) == len(rows[0]) for r in rows), (name, rows[:3])
    assert rows[0][:len(first)] == first, (name, rows[0])
names = [r[0] for r in csv.reader(open("summary.csv"))][1:]
assert names == ["amb", "p[1,1]", "p[1,2]", "p[2,1]", "p[2,2]"], names
assert "p[2,2]_min" in next(csv.reader(open("sweep.csv")))
head = next(csv.reader(open("est.csv")))
assert {"p[1,1]", "p[2,2]", "sd_p[1,2]"} <= set(head), head
EOF

# Misspelt estimator options are refused with a suggestion, not ignored.
run estimate grid.tnet data.csv --case c --option sigma_meas=5
check "estimate --option sigma_meas=5: usage error suggesting sigma-meas" \
  eval '[ "$rc" = 2 ] && grep -q "has no option '"'"'sigma_meas'"'"'; did you mean '"'"'sigma-meas'"'"'" err.txt'
run invert data.csv --sensors 'p[1,1],p[1,2],p[2,1]' --tau 10 --option foo=bar
check "invert --option foo=bar: usage error" eval '[ "$rc" = 2 ] && grep -q "no option '"'"'foo'"'"'" err.txt'

finish
