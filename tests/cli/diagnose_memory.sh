#!/usr/bin/env bash
# diagnose's memory grows with the measured points by a bounded amount per data row (issue 51,
# item 12).
#
# A two-node network (the model's own with G1 = 0.52 instead of 0.5, 0.1 K noise, 1 s rows, the
# heater stepping every 2000 s) is diagnosed at two sizes with one worker thread, each under
# /usr/bin/time; the growth of the peak resident memory between them, per added row, is what a
# larger file adds (the fixed part, the program and its libraries, cancels out). The sizes are
# small, so the test is cheap on 2 cores, and the bound is per row, not per run: it does not
# depend on time. Measured on the shared 2-core machine (the heap's fragmentation moves it by a
# tenth): 1800-1891 bytes a row before the cuts of issue 51, 1385-1641 after them (the fit's
# residuals and Jacobian moved instead of copied, one covariance per refit, the replaced fit
# released before the next restart, the first step's residuals released once read), 1331 once
# every refit kept its residuals in single precision from its end (2026-11-29). The bound,
# 2200 bytes a row, sits a third above the largest measured after the cuts so that
# fragmentation never fails it: it fails when the candidates keep a third more per row (two more
# residual vectors of the measured points for each of the joint refits), not on the margin
# between the code before and after the cuts.
# docs/diagnose.md has the numbers of a 10^6-row file.
# Usage: diagnose_memory.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

if [ ! -x /usr/bin/time ]; then
  echo "SKIP: /usr/bin/time is not installed"
  exit 77
fi
PY=$(command -v python3) || { echo "SKIP: no python3"; exit 77; }

# Data: the exact 1 s step of the 2x2 linear network (by its eigenvalues), plain Python only.
cat >gen.py <<'EOF2'
import math, random, sys
rows, out, g1 = int(sys.argv[1]), sys.argv[2], float(sys.argv[3])
random.seed(51)
Ca, Cb, g2, g3 = 800.0, 400.0, 0.8, 0.3
a11, a12, a21, a22 = -(g1 + g2) / Ca, g2 / Ca, g2 / Cb, -(g2 + g3) / Cb
tr, det = a11 + a22, a11 * a22 - a12 * a21
d = math.sqrt(tr * tr / 4 - det)
l1, l2 = tr / 2 + d, tr / 2 - d
def fn(f):  # f(A) by Sylvester's formula for distinct eigenvalues
    c1, c2 = f(l1) / (l1 - l2), f(l2) / (l1 - l2)
    return [[c1 * (a11 - l2) - c2 * (a11 - l1), (c1 - c2) * a12],
            [(c1 - c2) * a21, c1 * (a22 - l2) - c2 * (a22 - l1)]]
E, B = fn(math.exp), fn(lambda l: (math.exp(l) - 1) / l)
x1 = x2 = P = 0.0
with open(out, "w") as f:
    f.write("time,P,a,b\n")
    for k in range(rows):
        if k % 2000 == 0:
            P = round(random.uniform(0, 30), 3)
        f.write(f"{k},{P},{20 + x1 + random.gauss(0, 0.1):.3f},{20 + x2 + random.gauss(0, 0.1):.3f}\n")
        u = P / Ca
        x1, x2 = E[0][0] * x1 + E[0][1] * x2 + B[0][0] * u, E[1][0] * x1 + E[1][1] * x2 + B[1][0] * u
EOF2

# peak RSS in kB of a diagnosis of ROWS rows (the data file data-ROWS.csv)
peak() {
  local rows=$1
  "$PY" gen.py "$rows" "data-$rows.csv" 0.52 || return 1
  cat >"m$rows.tnet" <<EOF2
param G1 = 0.5 [W/K] range 0.1 .. 2
boundary room T = 20
node a C = 800
node b C = 400
conductance g1 a room G = G1
conductance g2 a b G = 0.8
conductance g3 b room G = 0.3
heater h a P = table(data, "P")
case run {
  duration = $((rows - 1))
  initial = data
  data "data-$rows.csv" { a = a; b = b }
}
EOF2
  /usr/bin/time -f "%M" -o "rss-$rows.txt" "$TN" diagnose "m$rows.tnet" --threads 1 \
    --json "r$rows.json" >"out-$rows.txt" 2>"err.txt" || return 1
  tail -n 1 "rss-$rows.txt"
}

small=4000
large=24000
kb_small=$(peak $small)
check "diagnose of $small rows succeeds" test -n "$kb_small"
kb_large=$(peak $large)
check "diagnose of $large rows succeeds" test -n "$kb_large"
check "it finds the changed conductance (G1 recalibrated)" grep -Eq "parameter \[\]: G1 = 0\.5[12]" "out-$large.txt"
if [ -n "$kb_small" ] && [ -n "$kb_large" ]; then
  per_row=$(((kb_large - kb_small) * 1024 / (large - small)))
  echo "peak RSS: $kb_small kB at $small rows, $kb_large kB at $large rows: $per_row bytes a row"
  if [ "$per_row" -lt 2200 ]; then
    ok "memory grows by less than 2200 bytes a row ($per_row)"
  else
    bad "memory grows by less than 2200 bytes a row" "$per_row bytes a row"
  fi
fi
finish
