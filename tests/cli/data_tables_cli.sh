#!/usr/bin/env bash
# Tables and data files as the real-data probes of issue 51 found them: a bad cell of the case's
# data file read by table(data, ...) is an error (it was 0 K), an absolute-time table of the model
# is on the case's clock (it was 600 s early), dates that do not exist and impossible zones are
# refused, cells beyond a double say that they overflow or underflow, weights near 1e308 average
# right. Usage: data_tables_cli.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

# The value of a column in the row of a time.
value_at() {
  python3 -c "import csv,sys; print([r[sys.argv[2]] for r in csv.DictReader(open(sys.argv[1])) if float(r['time']) == float(sys.argv[3])][0])" "$@"
}

# ----------------------------------------------------------------------------- table(data, ...) cells
cat >cells.tnet <<'EOF'
boundary room T = table(data, "T")
node a C = 100
conductance g a room G = 1
case c { duration = 100; output = 50; data "cells.csv" { a = a } }
EOF
for cell in x oops 1e-400; do
  printf 'time,T,a\n0,25,20\n50,%s,21\n100,30,22\n' "$cell" >cells.csv
  run simulate cells.tnet -o cells_out.csv
  check "table(data, \"T\") with a cell '$cell': exit 1 at cells.csv row 3 column 2 (was -273.15 degC)" \
    eval 'test "$rc" -eq 1 && grep -q "cells.csv:3:2: .$cell. " err.txt && test ! -s cells_out.csv'
done
printf 'time,T,a\n0,25,20\n50,1e-400,21\n100,30,22\n' >cells.csv
run lint cells.tnet
check "  ... 1e-400 underflows, says the message" \
  eval 'test "$rc" -eq 1 && grep -q "cells.csv:3:2: .1e-400. underflows: its magnitude is below the smallest number" out.txt'
printf 'time,T,a\n0,25,20\n50,-1e400,21\n100,30,22\n' >cells.csv
run lint cells.tnet
check "  ... -1e400 overflows" eval 'test "$rc" -eq 1 && grep -q "cells.csv:3:2: .-1e400. overflows" out.txt'
printf 'time,T,a\n0,25,20\n50,4e-320,21\n100,30,22\n' >cells.csv
run lint cells.tnet
check "  ... a subnormal 4e-320 is a number (0 degC here: exit 0)" test "$rc" -eq 0

# ----------------------------------------------------------------------------- absolute-time tables
# The data file's clock starts 600 s before the table's first row: P is 100 W from t = 600 s,
# 110 W from 1200 s, in the model and in a case override alike.
python3 -c "
print('stamp,P')
for k in range(5): print(f'{1600000600 + 600 * k},{100 + 10 * k}')" >abs2.csv
python3 -c "
print('stamp,air')
for k in range(6): print(f'{1600000000 + 600 * k},20')" >clock.csv
cat >model_level.tnet <<'EOF'
boundary room T = 20
node air C = 1e9
conductance g air room G = 1
heater h air P = table("abs2.csv", "P", time = "stamp" [unix s])
case c { duration = 3000; output = 600; data "clock.csv" time = "stamp" [unix s] }
EOF
sed 's/^heater h air P = .*/heater h air P = 0/; s/output = 600;/output = 600; h.P = table("abs2.csv", "P", time = "stamp" [unix s]);/' \
  model_level.tnet >override.tnet
for m in model_level override; do
  run simulate $m.tnet --flows flows_$m.csv -o /dev/null
  check "$m: P = 100 W at t = 0 and 600 s, 110 W at 1200 s (the data file's clock)" \
    eval 'test "$rc" -eq 0 && test "$(value_at flows_$m.csv h@air 0)" = 100 &&
          test "$(value_at flows_$m.csv h@air 600)" = 100 && test "$(value_at flows_$m.csv h@air 1200)" = 110'
done
cat >two_cases.tnet <<'EOF'
boundary room T = 20
node air C = 1e9
conductance g air room G = 1
heater h air P = table("abs2.csv", "P", time = "stamp" [unix s])
case c { duration = 3000; output = 600; data "clock.csv" time = "stamp" [unix s] }
case late { duration = 600; output = 600; data "late.csv" time = "stamp" [unix s] }
EOF
printf 'stamp,air\n1600001200,20\n1600001800,20\n' >late.csv
run simulate two_cases.tnet --case late --flows late_flows.csv -o /dev/null
check "a second case on another clock reads the table on its own (110 W at its start)" \
  eval 'test "$rc" -eq 0 && test "$(value_at late_flows.csv h@air 0)" = 110'

# ----------------------------------------------------------------------------- ISO dates and zones
cat >iso.tnet <<'EOF'
boundary room T = 20
node a C = 100
conductance g a room G = 1
case c { duration = 60; data "iso.csv" time = "when" [iso] }
EOF
for bad in "2021-02-30T00:00:00Z|2021-02 has no day 30 (it has 28 days)" \
  "2021-02-29T00:00:00Z|2021-02 has no day 29 (it has 28 days)" \
  "2021-04-31 10:00|2021-04 has no day 31" \
  "2021-13-01T00:00Z|there is no month 13" \
  "2021-01-01T25:00Z|the time of day lies outside 00:00 .. 24:00" \
  "2021-01-01T24:30Z|the time of day lies outside 00:00 .. 24:00" \
  "2021-01-01T10:00+99:99|a time zone lies within -12:00 .. +14:00" \
  "2021-01-01T10:00+05:60|a time zone lies within -12:00 .. +14:00"; do
  IFS='|' read -r stamp why <<<"$bad"
  printf 'when,a\n2021-01-01T00:00:00Z,20\n%s,21\n' "$stamp" >iso.csv
  run lint iso.tnet
  check "ISO stamp '$stamp': exit 1 at row 3 column 1: $why" \
    eval 'test "$rc" -eq 1 && grep -qF "iso.csv:3:1: '"'"'$stamp'"'"' is not a date and time: $why" out.txt'
done
printf 'when,a\n2020-02-28T00:00:00Z,20\n2020-02-29T00:00:00+14:00,21\n2020-03-01T00:00:00Z,21\n' >iso.csv
run lint iso.tnet
check "2020-02-29 (a leap day) and the zone +14:00 are read (exit 0)" test "$rc" -eq 0

finish
