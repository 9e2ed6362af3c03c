#!/usr/bin/env bash
# The command-line contract of `thermnet sensitivity` and `thermnet simulate --samples`: table and
# ranking, --json, --elements, --case, determinism across --threads, bands CSV columns, --plot,
# and usage errors. Usage: sensitivity_cli.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

# run CMD...: runs thermnet, stores stdout/stderr/exit status in out.txt/err.txt/$rc

# ----------------------------------------------------------------------------- models
# One node cooling through G (dominant, ranged) with a weak ranged heater P; no data.
cat >one.tnet <<'EOF2'
model one
param Gp = 2 [W/K] range 1 .. 3
param Pp = 0.1 [W] range 0 .. 0.2
param Cn = 1000 [J/K]
boundary amb T = 0
node n C = Cn T0 = 20
node m C = 500 T0 = 10
conductance g n amb G = Gp
conductance gm n m G = 0.5
heater h n P = Pp
case run { duration = 2000; output = 100 }
case other { duration = 1000; output = 100 }
EOF2
# Data for one node of a two-node model: outputs are then the measured node only.
cat >measured.tnet <<'EOF2'
param Ga = 1 [W/K] range 0.5 .. 2
boundary amb T = 0
node a C = 400 T0 = 30
node b C = 400 T0 = 30
conductance g a amb G = Ga
conductance gab a b G = 1
case fit { duration = 600; output = 60; data "fit.csv" }
EOF2
printf 'time,a\n0,30\n300,12\n600,6\n' >fit.csv

# ----------------------------------------------------------------------------- sensitivity
run sensitivity one.tnet --case run
check "sensitivity exits 0" test "$rc" -eq 0
check "table header names the output nodes and a total" \
  grep -Eq '^rank +factor +range/value +n +m +total$' out.txt
check "the dominant param is ranked first" grep -Eq '^ +1 +Gp ' out.txt
check "fixed params are listed too" grep -Eq '^ +[0-9]+ +Cn ' out.txt
check "element keys only with --elements" bash -c '! grep -q "g.G" out.txt'
check "simulation count goes to stderr" grep -q 'simulations' err.txt

run sensitivity one.tnet --case run --elements --json s.json --threads 1
check "--elements --json exits 0" test "$rc" -eq 0
check "--elements adds element keys and capacities" \
  bash -c 'grep -q "g.G" out.txt && grep -q "n.C" out.txt && grep -q "h.P" out.txt'
check "JSON has matrix, ranking, factors, outputs" python3 - <<'PY'
import json
d = json.load(open("s.json"))
assert d["ranking"][0] == "Gp", d["ranking"]
assert d["outputs"] == ["n", "m"], d["outputs"]
assert len(d["matrix"]) == len(d["factors"])
names = [f["name"] for f in d["factors"]]
assert "g.G" in names and "n.C" in names
f = d["factors"][names.index("Gp")]
assert f["lo"] == 1 and f["hi"] == 3 and f["scale"] == 2
assert d["simulations"] == 1 + 2 * len(names)
PY
cp s.json s1.json
run sensitivity one.tnet --case run --elements --json s.json --threads 2
check "same JSON whatever --threads" cmp -s s.json s1.json

run sensitivity one.tnet
check "without data every case is used" grep -q 'cases: run, other' out.txt

run sensitivity measured.tnet --json m.json
check "with data only the measured nodes are outputs" \
  python3 -c 'import json; assert json.load(open("m.json"))["outputs"] == ["a"]'

run sensitivity one.tnet --case nowhere
check "an unknown case is a usage error (exit 2)" test "$rc" -eq 2
run sensitivity missing.tnet
check "an unreadable model is a usage error (exit 2)" test "$rc" -eq 2
run sensitivity one.tnet --json /nonexistent/dir/s.json
check "an unwritable --json is exit 2" test "$rc" -eq 2

# ----------------------------------------------------------------------------- simulate --samples
run simulate one.tnet --case run --samples 20 --seed 4 -o b.csv --plot b.svg --threads 1
check "simulate --samples exits 0" test "$rc" -eq 0
check "bands CSV header: NODE_min, NODE_p5, NODE_p50, NODE_p95, NODE_max" \
  test "$(head -1 b.csv)" = "time,amb_min,amb_p5,amb_p50,amb_p95,amb_max,n_min,n_p5,n_p50,n_p95,n_max,m_min,m_p5,m_p50,m_p95,m_max"
check "one row per output time" test "$(wc -l <b.csv)" -eq 22
check "bands are ordered min <= p5 <= p50 <= p95 <= max" python3 - <<'PY'
import csv
for row in csv.DictReader(open("b.csv")):
    for n in ("n", "m"):
        v = [float(row[f"{n}_{c}"]) for c in ("min", "p5", "p50", "p95", "max")]
        assert v == sorted(v), (row["time"], n, v)
PY
check "--plot writes an SVG" grep -q '<svg' b.svg
check "the sample count goes to stderr" grep -q '20 samples of 2 ranged params, 0 failed' err.txt
run simulate one.tnet --case run --samples 20 --seed 4 -o b2.csv --threads 2
check "same bands whatever --threads" cmp -s b.csv b2.csv
run simulate one.tnet --case run --samples 20 --seed 5 -o b3.csv
check "another seed gives other bands" bash -c '! cmp -s b.csv b3.csv'
run simulate one.tnet --case run --samples 10 --percentiles 2.5,50,97.5
check "--percentiles names the columns" \
  bash -c 'head -1 out.txt | grep -q "n_min,n_p2.5,n_p50,n_p97.5,n_max"'
run simulate one.tnet --case run --samples 10 --percentiles 0
check "a percentile outside (0, 100) is a usage error (exit 2)" test "$rc" -eq 2
run simulate one.tnet --case run -o plain.csv
check "without --samples simulate is unchanged" test "$(head -1 plain.csv)" = "time,amb,n,m"

finish
