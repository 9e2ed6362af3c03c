#!/usr/bin/env bash
# Temperatures below absolute zero never pass silently: a run that drives a node below 0 K stops
# with the node, the time it crossed and a hint; a steady state below 0 K is refused the same way;
# the consistent start of a node without heat capacity balanced by radiation picks the physical
# (positive) root of T^4. Expected values are analytic. Usage: physics_guards_cli.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

# near VALUE EXPECTED TOL: VALUE is a number and |VALUE - EXPECTED| <= TOL.
near() {
  [[ "$1" =~ ^-?[0-9]+(\.[0-9]*)?([eE][-+]?[0-9]+)?$ ]] || return 1
  awk -v v="$1" -v e="$2" -v t="$3" 'BEGIN { d = v - e; if (d < 0) d = -d; exit !(d <= t) }'
}

# ------------------------------------------------ a massless node: heater against weak radiation
# massless_case T0 P EPS INITIAL: a node without capacity between a heater of P W and radiation
# (A = 1e-4 m^2, both emissivities EPS) to space at 3.15 K, from start T0 (degC).
massless_case() {
  cat >massless.tnet <<EOF
model massless
boundary space T = -270
node s C = 0 $1
radiation r s space A = 1e-4 eps1 = $3 eps2 = $3
heater h s P = $2
case c { duration = 100; output = 50; $4 }
EOF
}
# P = eps sigma A (T^4 - Tb^4), eps = 1 / (2/EPS - 1): the positive root; the negative one (about
# -T) must never be chosen. From T0 = 1000 degC, IDA's modified Newton keeps the Jacobian of the
# start, whose T^4 slope is 600 times too small, and used to land at the negative root (-9380 degC).
for variant in "|1000|0.1|" "|1000|0.1|initial = steady" "T0 = 1000|1000|0.05|" "T0 = 1000|1|0.05|" \
  "T0 = 1e5|1e6|0.05|"; do
  IFS='|' read -r t0 p eps initial <<<"$variant"
  massless_case "$t0" "$p" "$eps" "$initial"
  expected=$(awk -v P="$p" -v e="$eps" \
    'BEGIN { k = 5.670374419e-8 * 1e-4 / (2 / e - 1); printf "%.4f", (P / k + 3.15^4)^0.25 - 273.15 }')
  rm -f massless.csv
  run simulate massless.tnet -o massless.csv
  s_end=$(tail -n 1 massless.csv 2>/dev/null | cut -d, -f3)
  check "massless node (${t0:-no T0}, P = $p W, eps = $eps${initial:+, $initial}): exit 0 at the physical root $expected degC" \
    eval 'test "$rc" -eq 0 && near "$s_end" "$expected" 0.01'
done

# ------------------------------------------------ a negative heater drives a node below 0 K
# C = 100 J/K, G = 0.01 W/K, P = -100 W from 20 degC: T(t) = 293.15 - 10000 (1 - exp(-t/1e4)) K
# crosses 0 K at t = -1e4 ln(1 - 0.029315) = 297.53 s.
cat >negheat.tnet <<'EOF'
model negheat
boundary amb T = 20
node n C = 100 T0 = 20
conductance g n amb G = 0.01
heater h n P = -100
case c { duration = 3600; output = 600 }
EOF
crossing=$(awk 'BEGIN { print -1e4 * log(1 - 293.15 / 1e4) }')
run simulate negheat.tnet -o negheat.csv
t_cross=$(sed -n 's/.*below absolute zero at t = \([0-9.e+-]*\) s.*/\1/p' err.txt)
check "negative heater: exit 1, node n below absolute zero with a hint, no CSV written" \
  eval 'test "$rc" -eq 1 && grep -q "node n falls below absolute zero" err.txt &&
        grep -q "negative heater" err.txt && test ! -e negheat.csv'
check "  ... at the analytic crossing time $crossing s (within 0.05 s), not at a step end" \
  near "$t_cross" "$crossing" 0.05

# ------------------------------------------------ a steady state below 0 K
cat >negsteady.tnet <<'EOF'
model negsteady
boundary amb T = 20
node n C = 100
conductance g n amb G = 0.01
heater h n P = -100
case c { duration = 60; initial = steady }
EOF
run simulate negsteady.tnet -o negsteady.csv
check "steady state below 0 K: exit 1 naming node n and its -9706.85 K (293.15 - 100/0.01)" \
  eval 'test "$rc" -eq 1 && grep -q "node n falls below absolute zero in the steady state" err.txt &&
        grep -q -- "-9706.85 K" err.txt && test ! -e negsteady.csv'

# ------------------------------------------------ a steady state far from the guess
# Three massless nodes: 100 kW into s, which radiates weakly to space and strongly to p; p reaches q
# only through 1e-6 W/K; q radiates to space. Newton's line search fails from the 20 degC guess; the
# steady solve walks there in pseudo-time and Newton finishes: every node balance closes.
cat >far.tnet <<'EOF'
model far
boundary space T = -270
node s C = 0
node p C = 0
node q C = 0
radiation r1 s space A = 1e-4 eps1 = 0.05 eps2 = 1
radiation r2 s p A = 1 eps1 = 0.9 eps2 = 0.9
conductance g p q G = 1e-6
radiation r3 q space A = 10 eps1 = 0.9 eps2 = 1
heater h s P = 1e5
heater h2 q P = 1e-3
EOF
run simulate far.tnet --steady --stats -o far.csv
check "steady state far from the guess: exit 0, found through the pseudo-transient walk" \
  eval 'test "$rc" -eq 0 && grep -q "kinsol+pseudo-transient" err.txt'
check "  ... temperatures of the closed form: s radiates 100 kW less what g carries, q radiates 1 mW plus it" python3 - <<'PY'
import csv
row = next(csv.DictReader(open("far.csv")))
K = {k: float(v) + 273.15 for k, v in row.items() if k != "time"}
sigma = 5.670374419e-8
gr1 = 1e-4 / (1 / 0.05 + 1 / 1 - 1)
gr3 = 10 / (1 / 0.9 + 1 / 1 - 1)
qg = 1e-6 * (K["p"] - K["q"])  # s and p are held together by r2 (2.7 MW/K): g carries s's rest
s = ((1e5 - qg) / (sigma * gr1) + K["space"] ** 4) ** 0.25
q = ((1e-3 + qg) / (sigma * gr3) + K["space"] ** 4) ** 0.25
assert abs(K["s"] - s) < 1e-5 and abs(K["p"] - s) < 1e-5 and abs(K["q"] - q) < 1e-6, (K, s, q)
PY

# ------------------------------------------------ a massless node pulled below 0 K at the start
cat >massneg.tnet <<'EOF'
model massneg
boundary amb T = 20
node a C = 100 T0 = 20
node s C = 0
conductance g a amb G = 1
conductance g2 s a G = 0.01
heater h s P = -100
case c { duration = 60; output = 10 }
EOF
run simulate massneg.tnet
check "massless node below 0 K at the consistent start: exit 1 naming node s, t = 0, both hints" \
  eval 'test "$rc" -eq 1 && grep -q "node s falls below absolute zero at t = 0 s" err.txt &&
        grep -q "negative heater" err.txt && grep -q "negative root" err.txt'

# ------------------------------------------------ values computed while the run goes on
# A value written as an expression of the time is checked at every time the solver evaluates it,
# not only at t = 0 (issue 31, item 9): the run stops with the statement's file:line:column and
# the time, exit 1, and no CSV.
# guard LABEL LINES PATTERN: a model whose lines (from line 5) go wrong after t = 0 stops there
guard() {
  cat >guard.tnet <<EOF
model guard
boundary air T = 0
node box C = 1000 T0 = 50
conductance g box air G = 1
$2
case c { duration = 1000; output = 100 }
EOF
  rm -f guard.csv
  "$TN" lint guard.tnet >lint.txt 2>&1
  lint_rc=$?
  pattern=$3
  run simulate guard.tnet -o guard.csv
  check "$1: lint accepts it (valid at t = 0); simulate exits 1 at guard.tnet:5:1 with the time" \
    eval 'test "$lint_rc" -eq 0 && test "$rc" -eq 1 && grep -q "guard.tnet:5:1" err.txt &&
          grep -qE "$pattern" err.txt && grep -qE "at t = [0-9.e+-]+ s" err.txt &&
          test ! -e guard.csv'
}
guard "a boundary falling below 0 K" "boundary cold T = 20 - time
conductance gc box cold G = 0.1" "T of boundary 'cold' must be above absolute zero"
guard "a switch leaving [0, 1]" \
  "switched_conductance lid box air G = 2 on = 1 - time / 500" "on of switched_conductance 'lid' must be"
guard "a thermostat's power turning negative" \
  "thermostat t box P = 30 - time / 10 on = 60 off = 70" "P of thermostat 't' must be"
guard "a power that is not finite" "heater h box P = sqrt(500 - time)" \
  "P of heater 'h' is not a finite number"

finish
