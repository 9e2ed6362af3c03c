#!/usr/bin/env bash
# The command-line contract of `thermnet calibrate`: the Table-3 style table, JSON fields, -o
# round-trips comments and layout, --plot, determinism across --threads, usage errors (exit 2),
# nothing to calibrate (exit 1) and Ctrl-C (SIGINT still writes the best result, exit 1).
# Usage: calibrate_cli.sh PATH/TO/thermnet
set -u

TN=${1:?usage: calibrate_cli.sh PATH/TO/thermnet}
WORK=$(mktemp -d "${TMPDIR:-/tmp}/thermnet_calibrate_cli.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
cd "$WORK" || exit 2
export CI=1 # no progress bar

pass=0
fail=0
ok() { pass=$((pass + 1)); echo "ok   - $1"; }
bad() { fail=$((fail + 1)); echo "FAIL - $1"; [ $# -gt 1 ] && printf '       %s\n' "$2"; }
check() { # check DESCRIPTION COMMAND...: passes when COMMAND succeeds
  local what=$1; shift
  if "$@"; then ok "$what"; else bad "$what" "$(head -c 600 err.txt 2>/dev/null)"; fi
}
# run CMD...: runs thermnet, stores stdout/stderr/exit status in out.txt/err.txt/$rc
run() { "$TN" "$@" >out.txt 2>err.txt; rc=$?; }
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
sed 's/"heat.csv"/"long.csv"/' cal.tnet >long.tnet
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

# nothing to calibrate: exit 1
run calibrate norange.tnet
check "no ranged param: exit 1" test "$rc" -eq 1
check "  ... with a clear message" grep -q 'no param .* has a range' err.txt
run calibrate nodata.tnet
check "no case with data: exit 1" test "$rc" -eq 1
check "  ... with a clear message" grep -q 'no case .* has measured data' err.txt
run calibrate cal.tnet --case nope
check "unknown --case: exit 1" test "$rc" -eq 1

# Ctrl-C: a long run interrupted by SIGINT still writes the best result, exit 1
rm -f int.json int.tnet
timeout --preserve-status -s INT 2 "$TN" calibrate long.tnet --method mc --samples 1000000 \
  --tolerance 100 --json int.json -o int.tnet >out.txt 2>err.txt
rc=$?
check "SIGINT: exit 1" test "$rc" -eq 1
check "SIGINT: says the best result was written" grep -q 'interrupted; best result so far written' err.txt
check "SIGINT: the table is printed" grep -Eq '^ *mc +[0-9]+ ' out.txt
check "SIGINT: JSON written with cancelled = true and fewer samples" \
  test "$(json int.json "j['cancelled'] and j['found'] and 0 < j['evaluations'] < 1000000")" = True
check "SIGINT: -o written" test -s int.tnet

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
