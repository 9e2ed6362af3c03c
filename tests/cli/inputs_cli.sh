#!/usr/bin/env bash
# Inputs that change over time, as issue 51 probed them: a case's override out of range is
# reported at the case's line, a value just outside a range shows the digits that put it there, a
# pole of a time expression is a located error (not CVODE's step size underflow), a table of a
# million rows is integrated (it ran out of steps unnamed), and a node thousands of degC hot in a
# model where nothing is that hot gets a note about the inputs' units.
# Usage: inputs_cli.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

# ----------------------------------------------------------------------------- where and how much
cat >override.tnet <<'EOF'
boundary room T = 20
node a C = 100
conductance g a room G = 1
switched_conductance s a room G = 1 on = 0.5
case c {
  duration = 600; output = 60
  s.on = 0.5 + sin(time / 100)
}
EOF
run simulate override.tnet -o /dev/null
check "a case's override out of [0, 1]: exit 1 at the case's line 7, not the declaration (line 4)" \
  eval 'test "$rc" -eq 1 && grep -q "^override.tnet:7:3: error: on of switched_conductance .s. must be in \[0, 1\] at every time of the run" err.txt &&
        ! grep -q "override.tnet:4:" err.txt'
cat >model_level.tnet <<'EOF'
boundary room T = 20
node a C = 100
conductance g a room G = 1
switched_conductance s a room G = 1 on = 0.5 + sin(time / 100)
case c { duration = 600; output = 60 }
EOF
run simulate model_level.tnet -o /dev/null
check "  ... and the same expression in the declaration is reported there (line 4)" \
  eval 'test "$rc" -eq 1 && grep -q "^model_level.tnet:4:1: error: on of switched_conductance .s. must be in \[0, 1\]" err.txt'

cat >digits.tnet <<'EOF'
boundary room T = 20
node a C = 100
conductance g a room G = 1
switched_conductance s a room G = 1 on = 1 + 1e-12 * time
case c { duration = 600; output = 60 }
EOF
run simulate digits.tnet -o /dev/null
check "1 + 1e-12 t leaves [0, 1]: the value shows its digits (was 'got 1')" \
  eval 'test "$rc" -eq 1 && grep -q "must be in \[0, 1\] at every time of the run, got 1\.0000000000[0-9]* at t = " err.txt'
printf 'boundary room T = 20\nnode a C = 100\nconductance g a room G = 1\nswitched_conductance s a room G = 1 on = 1.0000000001\ncase c { duration = 10 }\n' >digits2.tnet
run lint digits2.tnet
check "  ... and so does a constant read with the model (1.0000000001)" \
  eval 'test "$rc" -eq 1 && grep -q "got 1.0000000001" out.txt'
printf 'boundary room T = 20\nnode a C = 100\nconductance g a room G = 1\nswitched_conductance s a room G = 1 on = 1.5\ncase c { duration = 10 }\n' >digits3.tnet
run lint digits3.tnet
check "  ... while a value far outside keeps its short form (got 1.5)" \
  eval 'test "$rc" -eq 1 && grep -q "got 1.5 \[invalid-value\]" out.txt'

# ----------------------------------------------------------------------------- a pole
cat >pole.tnet <<'EOF'
boundary room T = 20
node a C = 100
conductance g a room G = 1
heater h a P = 5 * tan(time / 100)
case c { duration = 600; output = 60 }
EOF
run simulate pole.tnet -o /dev/null
check "tan(time / 100): exit 1 at the expression (4:16), growing without bound near t = 157.08 s" \
  eval 'test "$rc" -eq 1 && grep -q "^pole.tnet:4:1: error: P of heater .h. grows without bound near t = 157.07963" err.txt &&
        grep -q "\[invalid-value\]" err.txt && ! grep -q "step size underflow" err.txt'
sed 's/^heater h a P = .*/heater h a P = 0/; s/output = 60 }/output = 60; h.P = 1 \/ (time - 100) }/' pole.tnet >pole_case.tnet
run simulate pole_case.tnet -o /dev/null
check "1 / (time - 100) in a case: exit 1 at the case's line, near t = 100 s" \
  eval 'test "$rc" -eq 1 && grep -q "^pole_case.tnet:5:.*P of heater .h. grows without bound near t = 100" err.txt'

# ----------------------------------------------------------------------------- a million rows
python3 -c "
import math
print('time,P')
for k in range(1000000): print(f'{k},{5 + math.sin(k / 100):.4f}')" >big.csv
cat >big.tnet <<'EOF'
boundary room T = 20
node a C = 100
conductance g a room G = 1
heater h a P = table("big.csv", "P")
case c { duration = 999999; output = 100000 }
EOF
run simulate big.tnet -o big_out.csv
check "a table of 10^6 rows is integrated to the end (exit 0; it ran out of steps at 499,865 s)" \
  eval 'test "$rc" -eq 0 && tail -1 big_out.csv | grep -q "^999999,"'

# ----------------------------------------------------------------------------- the unit trap
mkdir -p trap && cd trap || exit 2
printf 'time,Q1\n0,50\n600,50\n' >in.csv
cat >trap.tnet <<'EOF'
param P1 = 0.04 [W/%]
boundary amb T = 20
node T1 C = 10
conductance g T1 amb G = 0.065
heater h1 T1 P = P1 * table("in.csv", "Q1")
case c { duration = 600; output = 60 }
EOF
run simulate trap.tnet -o out.csv
check "W/% times a bare percent column (200 W into 10 J/K): exit 0, a note naming T1 and the unit hint" \
  eval 'test "$rc" -eq 0 && test -s out.csv &&
        grep -q "thermnet simulate: note: node .T1. reaches [0-9]* degC (t = [0-9]* s), though no boundary or start temperature of the model is above 1000 degC" err.txt &&
        grep -q "table(\"in.csv\", \"Q\") \[%\]" err.txt'
sed 's/table("in.csv", "Q1")/table("in.csv", "Q1") [%]/' trap.tnet >right.tnet
run simulate right.tnet -o out.csv
check "  ... with [%] after the table: 2 W, no note" eval 'test "$rc" -eq 0 && ! grep -q "note" err.txt'
sed 's/boundary amb T = 20/boundary amb T = 1500/' trap.tnet >furnace.tnet
run simulate furnace.tnet -o out.csv
check "  ... and no note in a furnace (a boundary at 1500 degC)" \
  eval 'test "$rc" -eq 0 && ! grep -q "note" err.txt'
cd .. || exit 2

finish
