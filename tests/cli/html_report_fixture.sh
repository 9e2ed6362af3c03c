# The fixture of the report-page tests (sourced in the scratch folder): m.tnet, two cases of a
# two-node model with a loss of node a to the air that the model lacks (so diagnose finds it), and
# their data, integrated here by classical Runge-Kutta (not by thermnet) with seeded noise of
# 0.05 K. A data file's name and a param's description hold markup and ampersands: the pages must
# show them escaped. Sets PY, DATA1 and DATA2.
PY=${PY:-/usr/bin/python3}
# The data file's name holds markup and an ampersand: the page must show it, escaped.
DATA1='d<script>alert(1)&1.csv'
DATA2='d2.csv'

"$PY" - "$DATA1" "$DATA2" <<'EOF'
import math, random, sys
random.seed(54)
def run(path, ta, a0, b0, hours):
    # truth: a --2 W/K-- b --1 W/K-- amb, and a --0.8 W/K-- amb (the loss the model lacks)
    Ca, Cb, Gab, Gb, Ga = 5000.0, 3000.0, 2.0, 1.0, 0.8
    def f(a, b):
        return ((Gab * (b - a) + Ga * (ta - a)) / Ca, (Gab * (a - b) + Gb * (ta - b)) / Cb)
    a, b, t, dt = a0, b0, 0.0, 1.0
    rows = ["time,a,b"]
    end = int(hours * 3600)
    for k in range(end + 1):
        if k % 60 == 0:
            rows.append(f"{k},{a + random.gauss(0, 0.05):.4f},{b + random.gauss(0, 0.05):.4f}")
        if k == end:
            break
        k1 = f(a, b); k2 = f(a + dt / 2 * k1[0], b + dt / 2 * k1[1])
        k3 = f(a + dt / 2 * k2[0], b + dt / 2 * k2[1]); k4 = f(a + dt * k3[0], b + dt * k3[1])
        a += dt / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        b += dt / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
    open(path, "w").write("\n".join(rows) + "\n")
run(sys.argv[1], 20.0, 50.0, 20.0, 2)
run(sys.argv[2], 20.0, 80.0, 30.0, 2)
EOF

cat >m.tnet <<'EOF'
model html_report
boundary amb T = 20
param Gab = 1.5 [W/K] range 0.5 .. 5 "<script>alert('param')</script> & the a-b link"
node a C = 5000 T0 = 50
node b C = 3000 T0 = 20
conductance gab a b G = Gab
conductance gb b amb G = 1
case warm { duration = 2 [h]; output = 60; data "d<script>alert(1)&1.csv" }
case hot { duration = 2 [h]; output = 60; a.T0 = 80; b.T0 = 30; data "d2.csv" }
EOF

# The prediction criterion's diagnosis fits a Kalman filter per candidate (minutes on the data
# above): short.tnet is a one-case copy on every third sample of the hot case's first hour.
awk -F, 'NR == 1 || ((NR - 2) % 3 == 0 && $1 <= 3600)' "$DATA2" >short.csv
sed -e '/^case warm/d' -e 's/"d2.csv"/"short.csv"/' -e 's/duration = 2 \[h\]/duration = 1 [h]/' \
  m.tnet >short.tnet
