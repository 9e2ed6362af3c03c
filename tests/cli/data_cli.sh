#!/usr/bin/env bash
# Data files as spreadsheets write them: a UTF-8 byte order mark is skipped, ';' separators are
# refused with a hint at row and column, and rows after the case's duration are a lint warning and
# are left out of a fit (they used to change it silently). Usage: data_cli.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

json() { python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print($2)" "$1"; }

cat >m.tnet <<'EOF'
model m
param G = 1 [W/K] range 0.2 .. 5
boundary amb T = 20
node n C = 1000 T0 = 50
conductance g n amb G = G
heater h n P = table("power.csv", "P")
case c { duration = 100; output = 10; data "meas.csv" }
EOF
printf 'time,P\n0,5\n100,5\n' >power.csv
# n cools from 50 degC towards 20 + 5/2 degC with G = 2 W/K: T = 22.5 + 27.5 exp(-t/500).
awk 'BEGIN { print "time,n"; for (t = 0; t <= 100; t += 10) printf "%d,%.4f\n", t, 22.5 + 27.5 * exp(-t / 500) }' >meas.csv
run simulate m.tnet -o plain.csv
check "the model simulates (exit 0)" test "$rc" -eq 0

# ----------------------------------------------------------------------------- byte order mark
printf '\xef\xbb\xbftime,P\n0,5\n100,5\n' >power.csv
run simulate m.tnet -o bom.csv
check "a table with a UTF-8 byte order mark is read like one without (exit 0, same CSV)" \
  eval 'test "$rc" -eq 0 && cmp -s bom.csv plain.csv'
printf '\xef\xbb\xbf' >bom_meas.csv && cat meas.csv >>bom_meas.csv
sed 's/"meas.csv"/"bom_meas.csv"/' m.tnet >bom.tnet
run lint bom.tnet
check "measured data with a byte order mark lint clean (exit 0)" test "$rc" -eq 0
printf 'time,P\n0,5\n100,5\n' >power.csv

# ----------------------------------------------------------------------------- ';' separators
printf 'time;n\n0;50\n100;45\n' >semi.csv
sed 's/"meas.csv"/"semi.csv"/' m.tnet >semi.tnet
run lint semi.tnet
check "';' separators: exit 1, row 1 column 1 of the file, a hint to export with ','" \
  eval 'test "$rc" -eq 1 && grep -q "semi.csv:1:1: the header separates its columns with .;." out.txt &&
        grep -q "export the file with .,. as the separator" out.txt'
printf 'time,n\n0,50\n10;49\n' >semirow.csv
sed 's/"meas.csv"/"semirow.csv"/' m.tnet >semirow.tnet
run lint semirow.tnet
check "a ';' inside a row: row 3 of the file, and the hint" \
  eval 'test "$rc" -eq 1 &&
        grep -q "semirow.csv:3: row has 1 fields, the header has 2 (fields are separated by .,., not .;.)" out.txt'

# ----------------------------------------------------------------------------- rows after the end
cp meas.csv long.csv
printf '200,90\n300,95\n' >>long.csv # far off the model: they would pull G down if used
sed 's/"meas.csv"/"long.csv"/' m.tnet >long.tnet
run lint long.tnet
check "rows after the duration: a data-beyond-duration warning naming the count, exit 0" \
  eval 'test "$rc" -eq 0 &&
        grep -q "warning: data file .long.csv. has 2 rows after the end of case .c. (100 s; last row at 300 s); they are not used \[data-beyond-duration\]" out.txt'
run lint m.tnet
check "  ... and none for data within the duration" eval 'test "$rc" -eq 0 && ! grep -q "data-beyond-duration" out.txt'
run calibrate m.tnet --method lm --json short.json
check "calibrate with the data in the duration (exit 0, G near 2 W/K)" \
  eval 'test "$rc" -eq 0 && test "$(json short.json "abs(j[\"params\"][\"G\"] - 2) < 0.01")" = True'
run calibrate long.tnet --method lm --json long.json
check "calibrate with the extra rows: the warning on stderr and the same fit (the rows are left out)" \
  eval 'test "$rc" -eq 0 && grep -q "data-beyond-duration" err.txt &&
        test "$(json long.json "j[\"params\"][\"G\"]")" = "$(json short.json "j[\"params\"][\"G\"]")"'
printf 'time,n\n0,nan\n150,40\n' >late.csv
sed 's/"meas.csv"/"late.csv"/' m.tnet >late.tnet
run calibrate late.tnet --method lm
check "no measured value within the duration: exit 1 saying so" \
  eval 'test "$rc" -eq 1 && grep -q "no measured value within the case.s duration of 100 s" err.txt'

finish
