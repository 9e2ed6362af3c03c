#!/usr/bin/env bash
# The command-line contract of `thermnet invert` and `thermnet estimate`: CSV in/out, --stream,
# errors with file:row:column, exit statuses. Usage: estimate_cli.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

TWIN="$HERE/../../models/digital_twin"

# Sensor data where the TIM-AB relation holds exactly (tau = 120 s, xi = 0.8), 0.5 s sampling.
/usr/bin/env awk 'BEGIN {
  print "time,A,B,C,D"; tau = 120; xi = 0.8
  for (k = 0; k < 400; k++) { t = k * 0.5
    C = 20 + 0.05*t + 1e-4*t*t; dC = 0.05 + 2e-4*t; D = 20 + 0.01*t + 3e-5*t*t
    B = tau*dC + (xi+1)*C - xi*D; dB = tau*2e-4 + (xi+1)*dC - xi*(0.01 + 6e-5*t)
    A = tau*dB + (xi+1)*B - xi*C
    printf "%g,%.10f,%.10f,%.10f,%.10f\n", t, A, B, C, D } }' >abcd.csv

run invert abcd.csv --sensors B,C,D --true A --window 50 --slide 5 -o est.csv --json rep.json
check "invert exits 0" test "$rc" -eq 0
check "invert header" test "$(head -1 est.csv)" = "time,A_est,tau_hat,xi_hat,A_true,A_err"
check "one output row per input row" test "$(wc -l <est.csv)" -eq 401
check "no estimate before the window is full" test "$(sed -n 2p est.csv | cut -d, -f2)" = ""
check "estimate from the 101st row" test -n "$(sed -n 102p est.csv | cut -d, -f2)"
check "exact data: tau-hat 120" awk -F, 'END { exit !($3 > 119.999 && $3 < 120.001) }' est.csv
check "metrics on stderr" grep -q "mean_relative_error" err.txt
check "json report has metrics" grep -q '"max_abs_error"' rep.json

run invert abcd.csv --sensors B,C,D --true A --mode full --filter savgol --gamma 0.3
check "full mode to stdout" test "$rc" -eq 0 -a "$(wc -l <out.txt)" -eq 401

# Streaming: the same rows through stdin give the same estimates, one line per row.
"$TN" invert --stream --sensors B,C,D --true A --window 50 --slide 5 <abcd.csv >stream.csv 2>/dev/null
check "stream exit 0 and same output as batch" cmp -s stream.csv est.csv

# Errors: file:row:column, statuses 1 (bad data) and 2 (usage, unreadable).
printf 'time,B,C,D\n0,1,2,3\n1,1,x,3\n' >bad.csv
run invert bad.csv --sensors B,C,D --window 1
check "bad cell: exit 1" test "$rc" -eq 1
check "bad cell: file:row:column" grep -q "bad.csv:3:3:" err.txt
printf 'time,B,C,D\n0,1,2,3\n1,1,x,3\n' | "$TN" invert --stream --sensors B,C,D --window 1 >/dev/null 2>err.txt
rc=$?
check "stream bad cell: <stdin>:3:3 and exit 1" test "$rc" -eq 1 -a -n "$(grep '<stdin>:3:3:' err.txt)"
printf 'time,B,C,D\n0,1,2,3\n1,1,-390,3\n' >cold.csv
run invert cold.csv --sensors B,C,D --window 1
check "data below absolute zero: exit 1 at its row and column (not an estimate of -390 degC)" \
  test "$rc" -eq 1 -a -n "$(grep 'cold.csv:3:3:.*below absolute zero' err.txt)"
printf 'time,B,C,D\n0,1,2,3\n1,True,2,3\n' >words.csv
run invert words.csv --sensors B,C,D --window 1
check "on/off words in a temperature column: exit 1 at its row and column" \
  test "$rc" -eq 1 -a -n "$(grep 'words.csv:3:2:' err.txt)"
run invert abcd.csv --sensors B,C,E --window 1
check "missing column: exit 1 naming it" test "$rc" -eq 1 -a -n "$(grep "'E'" err.txt)"
run invert nowhere.csv --sensors B,C,D --window 1
check "unreadable file: exit 2" test "$rc" -eq 2
run invert abcd.csv --sensors B,C,D --filter bogus
check "bad filter: exit 2" test "$rc" -eq 2
run invert abcd.csv --sensors B,C,D --window 50 -o /nonexistent/dir/x.csv
check "unwritable output: exit 2" test "$rc" -eq 2
run invert --help
check "help lists tim-ab and its options" grep -q "tim-ab" out.txt

# No estimate at all is a failure (exit 1 with a message), never an empty CSV with exit 0.
awk -F, 'NR == 1 { print; next } { print $1 ",5,5,5,5" }' abcd.csv >constant.csv
for variant in "abcd.csv --sensors B,C,D --tau 1e300|a window longer than the record" \
  "abcd.csv --sensors B,B,B --window 50|one sensor named three times" \
  "constant.csv --sensors B,C,D --window 50|constant data"; do
  IFS='|' read -r args what <<<"$variant"
  rm -f none.csv
  # shellcheck disable=SC2086 # the arguments are words
  run invert $args -o none.csv
  check "no estimate ($what): exit 1 saying so, no CSV written" \
    eval 'test "$rc" -eq 1 && grep -q "produced no estimate" err.txt && test ! -e none.csv'
done

# estimate: the digital twin, hidden lens centres scored against the synthetic truth columns.
run estimate "$TWIN/twin.tnet" "$TWIN/twin_data.csv" --case known \
  --measured window,l1_edge,l2_edge,barrel,inner,outer -o ekf.csv --plot ekf.svg
check "estimate exits 0" test "$rc" -eq 0
check "estimate header starts with the nodes" \
  test "$(head -1 ekf.csv | cut -d, -f1-4)" = "time,window,l1_edge,l1_centre"
check "hidden-node RMSE reported below 1 K" \
  awk '/rmse_l1_centre/ { found = 1; if ($5 + 0 >= 1.0) exit 1 } END { exit !found }' err.txt
check "plot written" grep -q "<svg" ekf.svg
head -40 "$TWIN/twin_data.csv" | "$TN" estimate "$TWIN/twin.tnet" --case known --stream \
  --measured barrel >stream_ekf.csv 2>/dev/null
check "estimate --stream: one row per input row" test "$(wc -l <stream_ekf.csv)" -eq 40
run estimate "$TWIN/twin.tnet" "$TWIN/twin_data.csv" --case twin --estimate-input barrel \
  --measured window,l1_edge,l2_edge,barrel,inner,outer -o input.csv
check "input estimate column" test "$(head -1 input.csv | cut -d, -f10)" = "q_barrel"
run estimate "$TWIN/twin.tnet" "$TWIN/twin_data.csv" --case known --measured nowhere
check "unknown measured column: exit 1" test "$rc" -eq 1
run estimate "$TWIN/twin.tnet" --stream --smooth
check "--smooth with --stream: exit 2" test "$rc" -eq 2

finish
