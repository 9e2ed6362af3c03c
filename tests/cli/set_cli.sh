#!/usr/bin/env bash
# `--set NAME=VALUE` and `--set NAME.KEY=VALUE` on every command that runs a model: each override
# gives the same output (bytes, or JSON without wall times) as the same edit made in a copy of the
# model file; sweeps over element keys equal separate --set runs; a --set beats the case's own
# setting; bad overrides are usage errors (exit 2) naming the option, on every command.
# Usage: set_cli.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

# box loses G to the ambient and is held between 17 and 20 degC by a thermostat; shelf is heated
# by h1 (a signal) and linked to box. Measured data: thermnet at other values, plus noise.
cat >base.tnet <<'EOF'
model setm
param G = 1 [W/K] range 0.5 .. 2
param T_amb = 0 [degC]
boundary amb T = T_amb
node box C = 1000 [J/K] T0 = 17
node shelf C = 500 [J/K]
conductance loss box amb G = G
conductance gs box shelf G = 0.5
conductance gsa shelf amb G = 0.2
heater h1 shelf P = pwl(0: 2, 2000: 4)
thermostat tstat box P = 30 [W] on = 17 off = 20
case c { duration = 3000 ; output = 30 ; initial = 17 ; data "meas.csv" }
case hot { duration = 3000 ; output = 30 ; initial = 17 ; h1.P = 6 ; T_amb = 10 }
EOF
sed -e 's/^param G = 1 \[W\/K\]/param G = 1.3 [W\/K]/' -e 's/P = pwl(0: 2, 2000: 4)/P = 2.5/' \
  -e 's/ ; data "meas.csv"//' base.tnet >truth.tnet
"$TN" simulate truth.tnet --case c -o truth.csv 2>/dev/null || { echo "cannot simulate"; exit 1; }
awk -F, 'BEGIN { srand(7) } NR == 1 { print "time,box,shelf"; next }
  { printf "%s,%.4f,%.4f\n", $1, $3 + 0.3 * (rand() - 0.5), $4 + 0.3 * (rand() - 0.5) }' \
  truth.csv >meas.csv

# edit FROM TO OUT: a copy of the model with one text replaced (which must occur).
edit() {
  grep -qF -- "$1" base.tnet || { echo "edit: '$1' not in the model"; exit 1; }
  python3 -c "import sys; t = open('base.tnet').read(); open(sys.argv[3], 'w').write(t.replace(sys.argv[1], sys.argv[2], 1))" "$1" "$2" "$3"
}
edit "P = pwl(0: 2, 2000: 4)" "P = 3" p3.tnet
edit "on = 17 off" "on = 16 off" on16.tnet
edit "node box C = 1000 [J/K]" "node box C = 2000 [J/K]" c2000.tnet
edit "param T_amb = 0 [degC]" "param T_amb = 5 [degC]" amb5.tnet
edit "boundary amb T = T_amb" "boundary amb T = 5" ambT5.tnet
edit "param G = 1 [W/K]" "param G = 1.7 [W/K]" g17.tnet
edit "P = 30 [W]" "P = 0.5 [W]" tstat05.tnet
# --set comes after the case's settings: where a case sets h1.P itself, --set h1.P=3 is the model
# with h1.P = 3 and no case setting of it.
sed -e 's/ ; h1.P = 6//' p3.tnet >p3_all.tnet

# same_run DESCRIPTION EDITED.tnet ARGS... -- SET-ARGS...: the command's stdout on the edited copy
# equals its stdout on the original with the --set items.
same_run() {
  local what=$1 edited=$2
  shift 2
  local args=() sets=()
  while [ "$1" != "--" ]; do args+=("$1"); shift; done
  shift
  sets=("$@")
  "$TN" "${args[@]/MODEL/$edited}" >edited.out 2>edited.err
  local rc_edited=$?
  "$TN" "${args[@]/MODEL/base.tnet}" "${sets[@]}" >set.out 2>err.txt
  rc=$?
  check "$what: exit 0" [ "$rc" = 0 -a "$rc_edited" = 0 ]
  check "$what: the same output as the edited model" cmp -s set.out edited.out
}

# ------------------------------------------------------------------ simulate
same_run "simulate --set h1.P=3 (a signal key set to a constant)" p3.tnet simulate MODEL --case c -- --set h1.P=3
same_run "simulate --set 'h1.P=3000 [mW]'" p3.tnet simulate MODEL --case c -- --set 'h1.P=3000 [mW]'
same_run "simulate --set tstat.on=16 (degC)" on16.tnet simulate MODEL --case c -- --set tstat.on=16
same_run "simulate --set 'tstat.on=289.15 [K]'" on16.tnet simulate MODEL --case c -- --set 'tstat.on=289.15 [K]'
same_run "simulate --set box.C=2000 (a node key)" c2000.tnet simulate MODEL --case c -- --set box.C=2000
same_run "simulate --set amb.T=5 (a boundary key)" ambT5.tnet simulate MODEL --case c -- --set amb.T=5
same_run "simulate --set T_amb=5 (a param)" amb5.tnet simulate MODEL --case c -- --set T_amb=5
same_run "simulate --steady with --set" tstat05.tnet simulate MODEL --case c --steady -- --set tstat.P=0.5
same_run "simulate --samples with --set" p3.tnet simulate MODEL --case c --samples 6 --seed 3 --threads 2 -- --set h1.P=3
cmp -s set.out edited.out && ! cmp -s set.out <("$TN" simulate base.tnet --case c --samples 6 --seed 3 2>/dev/null)
check "... and the override changes the bands" [ $? = 0 ]

# The case sets h1.P = 6 and T_amb = 10: --set comes after the case.
run simulate base.tnet --case hot --set h1.P=3 --set T_amb=5 --json hot_set.json -o /dev/null
check "--set over the case's own settings: exit 0" [ "$rc" = 0 ]
sed -e 's/ ; h1.P = 6 ; T_amb = 10//' base.tnet >hot_plain.tnet
"$TN" simulate hot_plain.tnet --case hot --set h1.P=3 --set T_amb=5 --json hot_plain.json -o /dev/null 2>/dev/null
"$TN" simulate base.tnet --case hot --json hot_case.json -o /dev/null 2>/dev/null
check "... the values of --set win over the case's" python3 - <<'EOF'
import json
a, b, c = (json.load(open(f)) for f in ("hot_set.json", "hot_plain.json", "hot_case.json"))
assert a["temperatures"] == b["temperatures"], "not the --set values"
assert a["temperatures"] != c["temperatures"], "the override changed nothing"
EOF

# ------------------------------------------------------------------ sweep over element keys
run sweep base.tnet --case c --param h1.P=1..3:3 --param tstat.on=16,17 --nodes box,shelf --threads 2 -o sweep.csv
check "sweep over element keys: exit 0" [ "$rc" = 0 ]
for p in 1 3; do
  "$TN" simulate base.tnet --case c --set h1.P=$p --set tstat.on=16 --summary single_$p.csv --nodes box,shelf -o /dev/null 2>/dev/null
done
check "sweep over element keys: rows equal separate --set runs (on in degC)" python3 - <<'EOF'
import csv
rows = list(csv.DictReader(open("sweep.csv")))
assert [(r["h1.P"], r["tstat.on"]) for r in rows] == [
    ("1", "16"), ("1", "17"), ("2", "16"), ("2", "17"), ("3", "16"), ("3", "17")], rows
for p in ("1", "3"):
    single = {r["node"]: r for r in csv.DictReader(open(f"single_{p}.csv"))}
    row = next(r for r in rows if r["h1.P"] == p and r["tstat.on"] == "16")
    for node in ("box", "shelf"):
        for stat in ("min", "max", "mean"):
            assert abs(float(row[f"{node}_{stat}"]) - float(single[node][stat])) < 1e-9, (p, node, stat)
assert rows[0]["shelf_mean"] != rows[4]["shelf_mean"]
EOF
same_run "sweep --set h1.P=3 with a param axis" p3.tnet sweep MODEL --case c --param G=0.5,2 --nodes box -- --set h1.P=3
# In case hot, which sets h1.P itself, a swept h1.P still takes the swept values.
run sweep base.tnet --case hot --param h1.P=1,3 --nodes shelf -o sweep_hot.csv
check "sweep in a case that sets the swept key: the swept values count" python3 - <<'EOF'
import csv
rows = list(csv.DictReader(open("sweep_hot.csv")))
assert rows[0]["shelf_mean"] != rows[1]["shelf_mean"], rows
EOF

# ------------------------------------------------------------------ calibrate
jsame() { # jsame A.json B.json: equal once wall times and the model's file name are dropped
  python3 - "$1" "$2" <<'EOF'
import json, sys
def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if not k.startswith("wall") and k != "model"}
    if isinstance(x, list):
        return [strip(v) for v in x]
    return x
a, b = (strip(json.load(open(f))) for f in sys.argv[1:3])
sys.exit(0 if a == b else 1)
EOF
}
"$TN" calibrate p3.tnet --method lm --json cal_edited.json --threads 2 >/dev/null 2>&1
run calibrate base.tnet --method lm --json cal_set.json --threads 2 --set h1.P=3
check "calibrate --set h1.P=3: exit 0" [ "$rc" = 0 ]
check "calibrate --set h1.P=3: the JSON of the edited model" jsame cal_set.json cal_edited.json
"$TN" calibrate g17.tnet --method lm --json cal_g_edited.json >/dev/null 2>&1
"$TN" calibrate base.tnet --method lm --json cal_g_base.json >/dev/null 2>&1
run calibrate base.tnet --method lm --json cal_g_set.json --set G=1.7
check "calibrate --set of a ranged param starts lm there: the JSON of the edited model" jsame cal_g_set.json cal_g_edited.json
check "... (a start the fit depends on: not the declared one's)" bash -c '! cmp -s cal_g_base.json cal_g_set.json'
run calibrate base.tnet --method lm --set G=3
check "calibrate --set of a ranged param outside its range: exit 2" [ "$rc" = 2 ]
check "... naming the option and the range" grep -q -- "--set: param 'G' = 3 W/K lies outside its range 0.5 W/K .. 2 W/K" err.txt
run calibrate base.tnet --method lm --set h1.P=3 -o calibrated.tnet
check "calibrate -o with --set: a note that the file keeps the model's values" grep -q "calibrated.tnet keeps the model's own values, not those of --set h1.P=3" err.txt

# ------------------------------------------------------------------ sensitivity
"$TN" sensitivity p3.tnet --case c --elements --json sens_edited.json --threads 2 >/dev/null 2>&1
run sensitivity base.tnet --case c --elements --json sens_set.json --threads 2 --set h1.P=3
check "sensitivity --set h1.P=3: exit 0" [ "$rc" = 0 ]
check "sensitivity --set h1.P=3: the JSON of the edited model" jsame sens_set.json sens_edited.json

# ------------------------------------------------------------------ diagnose
"$TN" diagnose p3_all.tnet --json diag_edited.json --threads 2 >diag_edited.txt 2>&1
run diagnose base.tnet --json diag_set.json --threads 2 --set h1.P=3
check "diagnose --set h1.P=3: exit 0" [ "$rc" = 0 ]
check "diagnose --set h1.P=3: the JSON of the edited model" jsame diag_set.json diag_edited.json

# ------------------------------------------------------------------ estimate
same_run "estimate --set h1.P=3" p3.tnet estimate MODEL --case c -- --set h1.P=3
"$TN" estimate base.tnet --case c --option sigma-meas=0.3 >opt.out 2>/dev/null
run estimate base.tnet --case c --set sigma-meas=0.3
check "estimate --set of a method option still reaches the method (as --option)" cmp -s out.txt opt.out
"$TN" estimate base.tnet --case c >plain.out 2>/dev/null
check "... and changes its result" bash -c '! cmp -s plain.out opt.out'

# ------------------------------------------------------------------ bad overrides
# bad_set DESCRIPTION EXPECTED-TEXT SET: exit 2 and the text on stderr, from simulate.
bad_set() {
  rm -f never.csv
  run simulate base.tnet --case c --set "$3" -o never.csv
  check "$1: exit 2" [ "$rc" = 2 ]
  check "$1: says '$2'" grep -qF -- "$2" err.txt
  check "$1: nothing written" [ ! -e never.csv ]
}
bad_set "unknown element" "--set: the model has no node, boundary or element 'h2'; did you mean 'h1'?" h2.P=3
bad_set "unknown key" "--set: heater 'h1' has no key 'PP'; did you mean 'P'?" h1.PP=3
bad_set "a node-valued key" "--set: 'sense' of thermostat 'tstat' names a node" tstat.sense=shelf
bad_set "not a number" "--set: 'abc' for 'h1.P' ('P' of 'h1') is not a number" h1.P=abc
bad_set "negative power where the key is non-negative" "--set: 'tstat.P' ('P' of 'tstat') must be >= 0, not -1 W" tstat.P=-1
bad_set "a unit of another dimension" "is in W, not K" "h1.P=3 [K]"
bad_set "below absolute zero" "must be above absolute zero (-273.15 degC), not -300 degC" tstat.on=-300
bad_set "unknown param" "--set: the model has no param 'Gx'; did you mean 'G'?" Gx=1
bad_set "no '='" "is not NAME=VALUE" h1.P
bad_set "on above off, against the element's own check" "'off' must be above 'on'" tstat.on=25
check "... located at the element, with the --set named" grep -q "base.tnet:11:1: error: --set tstat.on=25: thermostat 'tstat'" err.txt
check "... and a note naming the values set" grep -q "note: with the values set by --set tstat.on=25" err.txt
# Every command that runs a model refuses a bad --set the same way.
for cmd in "calibrate base.tnet" "diagnose base.tnet" "sensitivity base.tnet" \
  "sweep base.tnet --param G=1,2" "estimate base.tnet --case c"; do
  run $cmd --set h2.P=3
  check "$cmd --set h2.P=3: exit 2" [ "$rc" = 2 ]
  check "$cmd --set h2.P=3: names the option" grep -qF -- "--set: the model has no node, boundary or element 'h2'" err.txt
done
run sweep base.tnet --case c --param tstat.P=-1,2
check "sweep --param over a key with a bad value: exit 2" [ "$rc" = 2 ]
check "... naming --param" grep -qF -- "--param: 'tstat.P' ('P' of 'tstat') must be >= 0" err.txt

# Inside a submodel instance an element is set by its full name; a key of an alternative group
# the element does not use (radiation given by A, eps1, eps2) cannot replace that group.
cat >sub.tnet <<'EOF'
model subm
submodel box(a) {
  node n C = 100
  conductance g n a G = 1
  heater h n P = 1
}
boundary amb T = 20
box u1 amb
node r1 C = 10
radiation rad r1 amb A = 0.01 eps1 = 0.8 eps2 = 0.8
case c { duration = 100 }
EOF
run simulate sub.tnet --steady --set u1.h.P=5
check "--set u1.h.P=5 inside an instance: 20 degC + 5 W / 1 W/K" grep -q "^0,20.00000000,25.00000000,20.00000000$" out.txt
run simulate sub.tnet --steady --set u1.P=5
check "--set of an instance itself: exit 2, saying what to set" [ "$rc" = 2 ]
check "... what to set" grep -q "'u1' is an instance of submodel 'box'" err.txt
run simulate sub.tnet --steady --set rad.GR=1e-3
check "--set of a key outside the alternative the element uses: exit 2" [ "$rc" = 2 ]
check "... saying so" grep -q "radiation 'rad' is not given by 'GR' here" err.txt

finish
