#!/usr/bin/env bash
# Sensors (issue 51): a sensor never changes the network it reads (a lag used to corrupt its
# node), a lag too short to resolve is none (with a warning), an offset is a temperature
# difference in any unit, `initial = data` starts a node read through a sensor so that the reading
# equals the first measured value, and a sensor named like a node or a series of a node that
# several sensors read are lint errors. Usage: sensors_cli.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

# The largest |column - expected| over the rows of a CSV: column by name, expected a Python
# expression of t.
max_error() {
  python3 - "$1" "$2" "$3" <<'EOF'
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print(max(abs(float(r[sys.argv[2]]) - eval(sys.argv[3], {"t": float(r["time"]), "math": math}))
          for r in rows))
EOF
}
# The value of a column in the row of a time.
value_at() {
  python3 -c "import csv,sys; print([r[sys.argv[2]] for r in csv.DictReader(open(sys.argv[1])) if float(r['time']) == float(sys.argv[3])][0])" "$@"
}
below() { python3 -c "import sys; sys.exit(0 if abs(float(sys.argv[1])) < float(sys.argv[2]) else 1)" "$1" "$2"; }
# near VALUE EXPECTED: within 1e-6.
near() { python3 -c "import sys; sys.exit(0 if abs(float(sys.argv[1]) - float(sys.argv[2])) < 1e-6 else 1)" "$1" "$2"; }

# ----------------------------------------------------------------------------- a sensor changes nothing
# a: C = 100 J/K heated by 5 W through 1 W/K to a 20 degC room: a(t) = 25 - 5 exp(-t / 100). At
# the default tolerances a run is within 3e-3 K of it (5e-4 K without a sensor, 1e-3 K with one);
# a sensor with a short lag used to add its 1/tau to the node's Jacobian entry (declare() kept the
# slots of the pattern pass too): tau = 1e-6 s made a 170 degC, 1e-5 s 7.67 degC.
model() {
  printf 'boundary room T = 20\nnode a C = 100\nconductance g a room G = 1\nheater h a P = 5\n%s\n' "$2"
  printf 'case c { duration = %s; output = 10 }\n' "$1"
}
exact="25 - 5 * math.exp(-t / 100)"
model 300 "" >plain.tnet
run simulate plain.tnet -o plain.csv
check "without a sensor: a follows 25 - 5 exp(-t/100) within 3e-3 K" \
  eval 'test "$rc" -eq 0 && below "$(max_error plain.csv a "$exact")" 3e-3'
for tau in 1e-4 1e-3 0.01 1 100; do
  model 300 "sensor s a tau = $tau" >lag.tnet
  run simulate lag.tnet --sensors -o lag.csv
  check "a sensor with tau = $tau s leaves a on 25 - 5 exp(-t/100) within 3e-3 K" \
    eval 'test "$rc" -eq 0 && ! grep -q lag-too-short err.txt && below "$(max_error lag.csv a "$exact")" 3e-3'
done
# The reading of tau = 100 s: R' = (a - R) / tau, R(0) = 20: R = 25 - 5 (1 + t/100) exp(-t/100).
model 300 "sensor s a tau = 100" >lag.tnet
run simulate lag.tnet --sensors -o lag.csv
check "the reading of tau = 100 s is 25 - 5 (1 + t/100) exp(-t/100) within 3e-3 K" \
  eval 'test "$rc" -eq 0 && below "$(max_error lag.csv s "25 - 5 * (1 + t / 100) * math.exp(-t / 100)")" 3e-3'

# The issue's inputs (3000 s): far below 1e-7 of the duration a lag is none, with a warning.
for tau in 1e-5 1e-6 1e-12 1e-300 4e-320; do
  model 3000 "sensor s a tau = $tau" >tiny.tnet
  run simulate tiny.tnet --sensors -o tiny.csv
  check "tau = $tau s over 3000 s: exit 0, lag-too-short, a and the reading exact within 3e-3 K" \
    eval 'test "$rc" -eq 0 && grep -q lag-too-short err.txt && below "$(max_error tiny.csv a "$exact")" 1e-3 &&
          below "$(max_error tiny.csv s "$exact")" 3e-3'
done
model 3000 "sensor s a tau = 1e-6" >tiny.tnet
run lint tiny.tnet
check "lint: tau = 1e-6 s is a lag-too-short warning naming 1e-7 of the 3000 s, exit 0" \
  eval 'test "$rc" -eq 0 && grep -q "sensor .s.: tau = 1e-06 s is shorter than 1e-7 of the 3000 s of case .c. to resolve; it is taken as 0 (no lag) \[lag-too-short\]" out.txt'
model 3000 "sensor s a tau = 1" >ok.tnet
run lint ok.tnet
check "lint: tau = 1 s gives no warning" eval 'test "$rc" -eq 0 && ! grep -q "lag-too-short" out.txt'
printf 'boundary room T = 20\nnode a C = 100\nconductance g a room G = 1\nthermostat th a P = 5 on = 18 off = 20 lag = 1e-9\ncase c { duration = 3000 }\n' >thermo.tnet
run lint thermo.tnet
check "lint: a thermostat's lag of 1e-9 s over 3000 s is lag-too-short too" \
  eval 'test "$rc" -eq 0 && grep -q "thermostat .th.: lag = 1e-09 s is shorter than 1e-7" out.txt'

# On an arithmetic node (IDA): a = (5 + 20 + b) / 2 with b: C = 100, b' = (a - b)/100 ->
# b(t) = 25 - 5 exp(-t / 200), a = 12.5 + b / 2.
cat >arith.tnet <<'EOF'
boundary room T = 20
node a C = 0
node b C = 100
conductance g a room G = 1
conductance g2 a b G = 1
heater h a P = 5
sensor s a tau = TAU
case c { duration = 3000; output = 100 }
EOF
for tau in 1e-6 1e-12 0.5; do
  sed "s/TAU/$tau/" arith.tnet >arith_$tau.tnet
  run simulate arith_$tau.tnet --sensors -o arith.csv
  check "an arithmetic node read with tau = $tau s: exit 0 (was IDA_CONV_FAIL), a exact within 2e-3 K" \
    eval 'test "$rc" -eq 0 && below "$(max_error arith.csv a "12.5 + (25 - 5 * math.exp(-t / 200)) / 2")" 2e-3'
done

# ----------------------------------------------------------------------------- offset units
cat >offset.tnet <<'EOF'
boundary room T = 20
node a C = 100 T0 = 30
conductance g a room G = 1
sensor c a offset = 0.4 [degC]
sensor f a offset = 0.9 [degF]
sensor k a offset = 0.4 [K]
sensor b a offset = 0.4
case c { duration = 100; output = 50 }
EOF
run simulate offset.tnet --sensors -o offset.csv
check "offset = 0.4 [degC], 0.4 [K] and 0.4 read 0.4 K above the node (was 273.55 K above)" \
  eval 'test "$rc" -eq 0 && below "$(max_error offset.csv c "0.4 + 20 + 10 * math.exp(-t / 100)")" 3e-3 &&
        below "$(max_error offset.csv k "0.4 + 20 + 10 * math.exp(-t / 100)")" 3e-3 &&
        below "$(max_error offset.csv b "0.4 + 20 + 10 * math.exp(-t / 100)")" 3e-3'
check "offset = 0.9 [degF] reads 0.5 K above the node" \
  eval 'test "$rc" -eq 0 && below "$(max_error offset.csv f "0.5 + 20 + 10 * math.exp(-t / 100)")" 3e-3'
cat >offset2.tnet <<'EOF'
boundary room T = 20
param off = 30.4 [degC] - 30 [degC]
node a C = 100 T0 = 30
conductance g a room G = 1
sensor c a offset = off
sensor m a offset = -0.4 [degC]
case c { duration = 100; output = 50 }
EOF
run simulate offset2.tnet --sensors -o offset2.csv
check "a difference of degC values and a negative degC offset are differences too" \
  eval 'test "$rc" -eq 0 && below "$(max_error offset2.csv c "0.4 + 20 + 10 * math.exp(-t / 100)")" 3e-3 &&
        below "$(max_error offset2.csv m "-0.4 + 20 + 10 * math.exp(-t / 100)")" 3e-3'

# ----------------------------------------------------------------------------- initial = data
# The node must start so that its sensor reads the first measured value (27 degC).
start_case() { # SENSOR-LINE DATA-STATEMENT
  cat <<EOF
boundary room T = 20
node a C = 100
node b C = 100
conductance g a room G = 1
conductance g2 a b G = 1
heater h a P = 5
$1
case c { duration = 600; output = 60; initial = data; $2 }
EOF
}
printf 'time,a\n0,27\n60,27.5\n' >a.csv
printf 'time,s\n0,27\n60,27.5\n' >s.csv
printf 'time,x,y\n0,26,28\n60,27,28\n' >xy.csv
for variant in "sensor s a offset = 2|data \"a.csv\"|25" \
  "sensor s a offset = 2|data \"s.csv\"|25" \
  "sensor s a gain = 1.08|data \"a.csv\"|25" \
  "sensor s a offset = 2|data \"xy.csv\" { a = mean(x, y) }|25" \
  "sensor s a offset = 2|data \"xy.csv\" { s = mean(x: 1e308, y: 1e308) }|25"; do
  IFS='|' read -r sensor data start <<<"$variant"
  start_case "$sensor" "$data" >start.tnet
  run simulate start.tnet --sensors -o start.csv
  check "initial = data, $sensor, $data: a starts at $start degC, the reading at 27" \
    eval 'test "$rc" -eq 0 && near "$(value_at start.csv a 0)" "$start" && near "$(value_at start.csv s 0)" 27'
done
start_case "sensor s mean(a, b) offset = 1" 'data "s.csv"' >mean.tnet
run simulate mean.tnet --sensors -o mean.csv
check "initial = data through a sensor of mean(a, b): both start at 26 degC, the reading at 27" \
  eval 'test "$rc" -eq 0 && test "$(value_at mean.csv a 0)" = 26.00000000 &&
        test "$(value_at mean.csv b 0)" = 26.00000000 && test "$(value_at mean.csv s 0)" = 27.00000000'
start_case "sensor s mean(a, b) offset = 1" 'data "sab.csv"' >mean2.tnet
printf 'time,s,a\n0,27,25\n60,27.5,25.5\n' >sab.csv
run simulate mean2.tnet --sensors -o mean2.csv
check "  ... and with a measured directly at 25, b starts at 27 (the mean reads 26 + 1)" \
  eval 'test "$rc" -eq 0 && test "$(value_at mean2.csv a 0)" = 25.00000000 &&
        test "$(value_at mean2.csv b 0)" = 27.00000000 && test "$(value_at mean2.csv s 0)" = 27.00000000'

# ----------------------------------------------------------------------------- names and series
cat >named.tnet <<'EOF'
boundary room T = 20
node a C = 100
conductance g a room G = 1
sensor a a offset = 1
case c { duration = 100 }
EOF
run lint named.tnet
check "a sensor named like its node is a duplicate-name error at the sensor (its header was time,room,a,a)" \
  eval 'test "$rc" -eq 1 && grep -q "named.tnet:4:1: error: sensor .a. has the name of node .a.: its reading is a column of its own" out.txt &&
        grep -q "note: node .a. is declared here" out.txt'
cat >two.tnet <<'EOF'
boundary room T = 20
node a C = 100
conductance g a room G = 1
sensor s1 a offset = 1
sensor s2 a tau = 5
case c { duration = 100; data "two.csv" }
EOF
printf 'time,a\n0,20\n100,21\n' >two.csv
run lint two.tnet
check "two sensors on a and a column a: lint names both (data-sensor, exit 1)" \
  eval 'test "$rc" -eq 1 && grep -q "node .a. is read by the sensors .s1., .s2.: name the sensor the series is compared with.*\[data-sensor\]" out.txt'
printf 'time,s1\n0,20\n100,21\n' >two.csv
run lint two.tnet
check "  ... and a column naming one of them lints clean" test "$rc" -eq 0

finish
