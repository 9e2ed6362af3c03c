#!/usr/bin/env bash
# The command-line contract of `thermnet calibrate`: the Table-3 style table, JSON fields, -o
# round-trips comments and layout (also of included files, rewritten as copies beside OUT), a
# failed output writes nothing, --plot, determinism across --threads, usage errors (exit 2),
# nothing to calibrate (exit 1) and Ctrl-C (SIGINT still writes the best result, exit 1).
# Usage: calibrate_cli.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

# run CMD...: runs thermnet, stores stdout/stderr/exit status in out.txt/err.txt/$rc
# json FILE EXPR: evaluates a Python expression on the parsed JSON `j`, prints the result
json() { python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print($2)" "$1"; }

# ----------------------------------------------------------------------------- data
# The "measurements" are thermnet's own simulation at G = 2 W/K, h = 8 W/(m^2*K), plus noise.
cat >truth.tnet <<'EOF2'
model truth
param G = 2 [W/K]
param h = 8 [W/(m^2*K)]
boundary amb T = 20
node a C = 500 [J/K] T0 = 20
node b C = 300 [J/K] T0 = 20
conductance g a b G = G
convection cv b amb h = h A = 0.05 [m^2]
heater film a P = 10
case heat { duration = 3600; output = 60 }
case long { duration = 30000; output = 1 }
EOF2
"$TN" simulate truth.tnet --case heat -o sim.csv 2>/dev/null || { echo "cannot simulate"; exit 1; }
"$TN" simulate truth.tnet --case long -o simlong.csv 2>/dev/null || { echo "cannot simulate"; exit 1; }
# columns time,amb,a,b -> time,a,b with N(0, 0.1) noise (Box-Muller on a seeded awk rand)
awk -F, 'BEGIN { srand(42) } NR == 1 { print "time,a,b"; next }
  { u1 = 1 - rand(); u2 = rand(); r = sqrt(-2 * log(u1));
    printf "%s,%.4f,%.4f\n", $1, $3 + 0.1 * r * cos(6.2831853 * u2), $4 + 0.1 * r * sin(6.2831853 * u2) }' \
  sim.csv >heat.csv
cut -d, -f1,3,4 simlong.csv >long.csv

cat >cal.tnet <<'EOF2'
model cal
# calibration target: G and h are unknown
param G = 3 [W/K] range 0.5 .. 5   # conductance a-b
param  h = 5 [W/(m^2*K)]  range 2 .. 15 "convection b-ambient"
param C_b = 300 [J/K]

boundary amb T = 20     # ambient
node a C = 500 [J/K] T0 = 20
node b C = C_b T0 = 20
conductance g a b G = G
convection cv b amb h = h A = 0.05 [m^2]
heater film a P = 10
case heat { duration = 3600; output = 60; data "heat.csv" }
EOF2
sed 's/"heat.csv"/"long.csv"/; s/duration = 3600/duration = 30000/' cal.tnet >long.tnet
sed 's/ range [0-9.]* \.\. [0-9.]*//' cal.tnet >norange.tnet
grep -v 'data "' cal.tnet >nodata.tnet

# ----------------------------------------------------------------------------- checks
run calibrate cal.tnet --method mc --seed 3 -o calibrated.tnet --json report.json --plot fit.svg
check "mc run succeeds (exit 0)" test "$rc" -eq 0
check "table header has the Table 3 columns" \
  grep -q 'method.*samples.*evaluations.*accepted.*RMSE \[K\].*R².*G \[W/K\].*h \[W/(m^2\*K)\].*wall \[s\]' out.txt
check "table row: mc with 3000 samples by default" grep -Eq '^ *mc +3000 +3000 +[0-9]+ ' out.txt
check "JSON has exactly the contract's fields (and extras)" \
  test "$(json report.json "all(k in j for k in ['method','samples','evaluations','accepted','rmse','r2','params','wall_s'])")" = True
check "JSON: method, samples, units" \
  test "$(json report.json "j['method'], j['samples'], j['units']")" = "mc 3000 SI"
check "JSON: params recovered (G = 2 +- 0.25, h = 8 +- 0.7)" \
  test "$(json report.json "abs(j['params']['G'] - 2) < 0.25 and abs(j['params']['h'] - 8) < 0.7")" = True
check "JSON: RMSE near the noise (< 0.25 K) and R² > 0.99" \
  test "$(json report.json "j['rmse'] < 0.25 and j['r2'] > 0.99 and 0 < j['accepted'] <= j['evaluations']")" = True
diff cal.tnet calibrated.tnet >model.diff
check "-o changes only the two ranged param lines" \
  test "$(grep -c '^[<>]' model.diff)" -eq 4
check "-o keeps comments, spacing, range and doc of the rewritten lines" \
  grep -Eq '^param  h = [0-9.]+ \[W/\(m\^2\*K\)\]  range 2 \.\. 15 "convection b-ambient"$' calibrated.tnet
check "-o keeps the trailing comment of G" grep -Eq '^param G = [0-9.]+ \[W/K\] range 0\.5 \.\. 5   # conductance a-b$' calibrated.tnet
check "-o: the file minus the values is byte-identical" \
  cmp -s <(sed -E 's/^(param +[A-Za-z_]+ = )[0-9.e+-]+/\1X/' cal.tnet) \
         <(sed -E 's/^(param +[A-Za-z_]+ = )[0-9.e+-]+/\1X/' calibrated.tnet)
check "-o writes the JSON values (to 8 digits)" \
  test "$(json report.json "'%.8g' % j['params']['G']")" = "$(sed -nE 's/^param G = ([0-9.e+-]+) .*/\1/p' calibrated.tnet)"
"$TN" lint calibrated.tnet >/dev/null 2>&1
check "the calibrated model lints clean" test $? -eq 0
check "--plot writes an SVG" grep -q '<svg' fit.svg
check "the SVG has measured and simulated series" grep -q 'a measured' fit.svg

# -o when the ranged params live in an included file: the file is rewritten as a copy beside OUT
mkdir -p lib out
cat >lib/unknowns.tnet <<'EOF2'
# unknowns of the a-b test (included by inc.tnet)
param G = 3 [W/K] range 0.5 .. 5   # conductance a-b
param  h = 2 * 2.5 [W/(m^2*K)]  range 2 .. 15 "convection b-ambient"   # an expression
EOF2
cat >inc.tnet <<'EOF2'
model inc
include "lib/unknowns.tnet"   # the ranged params
param C_b = 300 [J/K]
boundary amb T = 20     # ambient
node a C = 500 [J/K] T0 = 20
node b C = C_b T0 = 20
conductance g a b G = G
convection cv b amb h = h A = 0.05 [m^2]
heater film a P = 10
case heat { duration = 3600; output = 60; data "heat.csv" }
EOF2
cp lib/unknowns.tnet unknowns.orig
cp inc.tnet inc.orig
run calibrate inc.tnet --method lm -o out/cal.tnet --json out/inc.json
check "-o with included params: exit 0" test "$rc" -eq 0
check "-o: the main file and a copy of the included file beside it" \
  test -s out/cal.tnet -a -s out/cal.unknowns.tnet -a "$(ls out | wc -l)" -eq 3
check "-o: says where the copy went" grep -q 'out/cal.unknowns.tnet (copy of lib/unknowns.tnet)' err.txt
check "-o: the user's files are untouched" eval 'cmp -s lib/unknowns.tnet unknowns.orig && cmp -s inc.tnet inc.orig'
check "-o: the main file includes the copy and reads the original data, nothing else changes" \
  test "$(diff inc.tnet out/cal.tnet | grep -c '^[<>]')" -eq 4 -a \
       "$(grep -c -e '^include "cal.unknowns.tnet"   # the ranged params$' -e 'data "../heat.csv"' out/cal.tnet)" -eq 2
check "-o: the copy keeps comments, spacing, ranges and docs" \
  cmp -s <(sed -E 's/^(param +[A-Za-z_]+ = )[^[]+ \[/\1X [/' unknowns.orig) \
         <(sed -E 's/^(param +[A-Za-z_]+ = )[^[]+ \[/\1X [/' out/cal.unknowns.tnet)
check "-o: an expression becomes the value in its unit" \
  grep -Eq '^param  h = [0-9.]+ \[W/\(m\^2\*K\)\]  range 2 \.\. 15 "convection b-ambient"   # an expression$' out/cal.unknowns.tnet
"$TN" lint out/cal.tnet --werror --allow-outside-paths >/dev/null 2>&1
check "-o: the calibrated model lints clean" test $? -eq 0
run calibrate out/cal.tnet --allow-outside-paths --method lm --samples 1 --json out2.json
check "-o: the calibrated model declares the fitted values and gives the fit's RMSE" \
  test "$(python3 -c "import json; a = json.load(open('out/inc.json')); b = json.load(open('out2.json'))
print(all(abs(b['declared'][k] / v - 1) < 1e-7 for k, v in a['params'].items()) and abs(b['rmse'] / a['rmse'] - 1) < 1e-3)")" = True

# a failure leaves no partial outputs
mkdir -p fail/cal.unknowns.tnet # a directory where the copy would go
run calibrate inc.tnet --method lm -o fail/cal.tnet --json fail/r.json --plot fail/fit.svg
check "an output that cannot be written: exit 2 with the reason" \
  test "$rc" -eq 2 -a -n "$(grep "cannot write 'fail/cal.unknowns.tnet'" err.txt)"
check "  ... and nothing written (no model, JSON, plot or temporary file)" test "$(ls -A fail)" = cal.unknowns.tnet
run calibrate inc.tnet --method lm -o lib/unknowns.tnet --json fail/r2.json
check "-o naming an included input: exit 2 naming both" \
  test "$rc" -eq 2 -a -n "$(grep "\-o 'lib/unknowns.tnet' would overwrite the included file '.*lib/unknowns.tnet'" err.txt)"
check "  ... the input untouched and nothing written" \
  eval 'cmp -s lib/unknowns.tnet unknowns.orig && test ! -e fail/r2.json'
run calibrate inc.tnet --method lm -o out/cal.tnet --json out/cal.tnet
check "-o and --json naming the same file: exit 2" test "$rc" -eq 2

# never in place: the model is an input of the run (also through a symlink)
cp inc.tnet inplace.tnet
cp inplace.tnet inplace.orig
ln -s inplace.tnet inplace_link.tnet
run calibrate inplace.tnet --method lm -o inplace.tnet
check "-o onto the model itself: exit 2 naming the model" \
  test "$rc" -eq 2 -a -n "$(grep "would overwrite the model 'inplace.tnet'" err.txt)"
run calibrate inplace.tnet --method lm -o inplace_link.tnet
check "-o onto a symlink to the model: exit 2" \
  test "$rc" -eq 2 -a -n "$(grep "would overwrite the model" err.txt)"
check "  ... the model untouched, the symlink still a symlink, no copy written" \
  eval 'cmp -s inplace.tnet inplace.orig && test -L inplace_link.tnet && test ! -e inplace.unknowns.tnet'
cp heat.csv heat.orig
run calibrate inc.tnet --method lm --json heat.csv
check "--json onto the measured data: exit 2 naming the data file, the data untouched" \
  eval 'test "$rc" -eq 2 && grep -q "would overwrite the data file .*heat.csv" err.txt && cmp -s heat.csv heat.orig'
run calibrate cal.tnet --method mc --samples 400 --seed 9 --threads 1 --json t1.json
r1=$rc
run calibrate cal.tnet --method mc --samples 400 --seed 9 --threads 2 --json t2.json
check "mc --threads 1 and 2 both succeed" test "$r1" -eq 0 -a "$rc" -eq 0
strip='{k: v for k, v in j.items() if k != "wall_s"}'
check "mc --threads 1 vs 2: identical JSON values" test "$(json t1.json "$strip")" = "$(json t2.json "$strip")"
run calibrate cal.tnet --method lhs --samples 400 --seed 9 --threads 1 --json l1.json
run calibrate cal.tnet --method lhs --samples 400 --seed 9 --threads 2 --json l2.json
check "lhs --threads 1 vs 2: identical JSON values" test "$(json l1.json "$strip")" = "$(json l2.json "$strip")"
check "lhs reports its method" test "$(json l1.json "j['method']")" = lhs

# ga reaches pagmo through libthermnet_pagmo_sga, which the executable loads on first use.
run calibrate cal.tnet --method ga --samples 200 --seed 3 --json ga.json
check "ga runs from the executable (its pagmo library is found and loaded)" test "$rc" -eq 0
check "ga improves the fit: RMSE < 0.3 K, G and h within their ranges" \
  test "$(json ga.json "j['method'] == 'ga' and j['rmse'] < 0.3 and 0.5 <= j['params']['G'] <= 5 and 2 <= j['params']['h'] <= 15")" = True

run calibrate cal.tnet --method mc --samples 50 --tolerance 0.01 --json none.json
check "no sample within the tolerance: exit 1" test "$rc" -eq 1
check "  ... with a clear message" grep -q 'no sample was within the tolerance' err.txt
check "  ... and found: false in the JSON" test "$(json none.json "j['found'], j['rmse']")" = "False None"

# usage errors: exit 2
run calibrate cal.tnet --samples -1
check "--samples -1: exit 2" test "$rc" -eq 2
run calibrate cal.tnet --samples 0
check "--samples 0: exit 2" test "$rc" -eq 2
run calibrate cal.tnet --method nope
check "--method nope: exit 2 listing the methods" test "$rc" -eq 2 -a -n "$(grep "unknown method 'nope'.*mc" err.txt)"
run calibrate cal.tnet --method lsh
check "--method lsh: suggests lhs" grep -q "did you mean 'lhs'" err.txt
run calibrate cal.tnet --tolerance abc
check "--tolerance abc: exit 2" test "$rc" -eq 2
run calibrate cal.tnet --threads -1
check "--threads -1: exit 2" test "$rc" -eq 2
run calibrate missing.tnet
check "unreadable model: exit 2" test "$rc" -eq 2
run calibrate cal.tnet --samples 10 -o no_such_dir/out.tnet
check "unwritable -o: exit 2" test "$rc" -eq 2
run calibrate --help
check "--help lists the registered methods" grep -q 'lhs:' out.txt
check "--help explains -o with included files" grep -q 'included files' out.txt

# nothing to calibrate: exit 1
run calibrate norange.tnet
check "no ranged param: exit 1" test "$rc" -eq 1
check "  ... with a clear message" grep -q 'no param .* has a range' err.txt
run calibrate nodata.tnet
check "no case with data: exit 1" test "$rc" -eq 1
check "  ... with a clear message" grep -q 'no case .* has measured data' err.txt
run calibrate cal.tnet --case nope
check "unknown --case: a usage error (exit 2)" test "$rc" -eq 2

# Ctrl-C: a long run interrupted by SIGINT still writes the best result, exit 1. The signal is sent
# once the run has used 2 s of CPU (samples evaluated, whatever the machine's load), at the latest
# after 300 s of waiting.
rm -f int.json int.tnet
"$TN" calibrate long.tnet --method mc --samples 1000000 --tolerance 100 --json int.json \
  -o int.tnet >out.txt 2>err.txt &
pid=$!
ticks=$(getconf CLK_TCK)
for _ in $(seq 3000); do
  cpu=$(awk '{print $14 + $15}' "/proc/$pid/stat" 2>/dev/null) || break
  [ "$cpu" -ge $((2 * ticks)) ] && break
  sleep 0.1
done
kill -INT "$pid" 2>/dev/null
wait "$pid"
rc=$?
check "SIGINT: exit 1" test "$rc" -eq 1
check "SIGINT: says the best result was written" grep -q 'interrupted; best result so far written' err.txt
check "SIGINT: the table is printed" grep -Eq '^ *mc +[0-9]+ ' out.txt
check "SIGINT: JSON written with cancelled = true and fewer samples" \
  test "$(json int.json "j['cancelled'] and j['found'] and 0 < j['evaluations'] < 1000000")" = True
check "SIGINT: -o written" test -s int.tnet

finish
