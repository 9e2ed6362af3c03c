#!/usr/bin/env bash
# Probes of issue 51 (part B) on the real-data surfaces, each a regression test:
#  - calibrate -o never writes through a symlink at a name it chose (a copy beside OUT), the
#    written model lints, and -o onto the model itself is refused with the model unchanged;
#  - a measured 1e300 is refused at its row and column; constant data give R² "undefined"
#    (text) and null (JSON), in calibrate and diagnose;
#  - lm names a param that has no effect;
#  - diagnose: --events may lie outside the model's folder; an unknown --case is a usage error
#    (exit 2); data on a boundary only is an error (exit 1); a boundary matched exactly is not
#    listed among the worst nodes;
#  - simulate --samples --sensors has bands of the sensors' readings.
# Usage: real_data_guards_cli.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

json() { python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print($2)" "$1"; }

# A first-order node heated from 20 degC towards 25 degC (tau = C/G = 100 s), its measurements.
cat >data.csv <<'EOF2'
time,a
0,20
100,23.16
200,24.32
300,24.75
400,24.91
500,24.97
600,24.99
700,25
800,25
900,25
1000,25
EOF2

# --------------------------------------------------------------- calibrate -o and symlinks
mkdir -p outside dir/sub
echo "victim content" >outside/victim.txt
cat >dir/sub/params.tnet <<'EOF2'
param G = 2 [W/K] range 0.1 .. 10
EOF2
cat >dir/sub/main.tnet <<'EOF2'
include "params.tnet"
boundary room T = 20
node a C = 100 T0 = 20
conductance g a room G = G
heater h a P = 5
case c { duration = 1000; output = 100; data "d.csv" }
EOF2
cp data.csv dir/sub/d.csv
ln -s ../../outside/victim.txt dir/sub/sub.params.tnet
cd dir/sub || exit 2
run calibrate main.tnet --method lm -o sub.tnet
check "calibrate -o beside a planted symlink succeeds (exit 0)" test "$rc" -eq 0
check "the file the symlink leads to is untouched" grep -qx "victim content" ../../outside/victim.txt
check "the symlink is still a symlink" test -L sub.params.tnet
check "the copy takes the next free name" test -f sub.params-2.tnet
check "the written model includes that copy" grep -q 'include "sub.params-2.tnet"' sub.tnet
check "the note names the copy" grep -q "sub.params-2.tnet (copy of params.tnet)" err.txt
run lint sub.tnet
check "the written model lints clean" test "$rc" -eq 0
run calibrate sub.tnet --method lm
check "the written model calibrates again (exit 0)" test "$rc" -eq 0
check "and starts at the fitted value (G about 1)" \
  python3 -c "import re,sys; v=float(re.search(r'param G = ([0-9.e+-]+)', open('sub.params-2.tnet').read()).group(1)); sys.exit(0 if abs(v-1)<0.05 else 1)"
# A FIFO at the name is not written into either: an error, nothing written (and no hang).
rm -f sub.params-2.tnet sub.tnet
mkfifo sub.params-2.tnet
run calibrate main.tnet --method lm -o sub.tnet --json sub.json
check "a FIFO at a chosen name is an error (exit 2)" test "$rc" -eq 2
check "naming it" grep -q "sub.params-2.tnet.*not a regular file" err.txt
check "nothing written" test ! -e sub.tnet -a ! -e sub.json
check "the FIFO is still a FIFO" test -p sub.params-2.tnet
rm -f sub.params-2.tnet sub.tnet
# OUT itself given as a symlink (a name the user gave) is written through, to what it names.
mkdir -p ../fitted
ln -s ../fitted/real.tnet link.tnet
run calibrate main.tnet --method lm -o link.tnet
check "-o through a symlink the user named succeeds (exit 0)" test "$rc" -eq 0
check "the symlink is kept" test -L link.tnet
check "the model lands where the symlink leads" test -f ../fitted/real.tnet
run lint link.tnet --allow-outside-paths
check "and lints (its copies and data resolve from there)" test "$rc" -eq 0
# -o onto the model itself: refused, the model untouched (the inputs are never modified).
cp main.tnet main.before
run calibrate main.tnet --method lm -o main.tnet
check "-o onto the model itself is refused (exit 2)" test "$rc" -eq 2
check "the refusal names the model" grep -q "would overwrite the model" err.txt
check "the model is unchanged" cmp -s main.tnet main.before
ln -s main.tnet alias.tnet
run calibrate main.tnet --method lm -o alias.tnet
check "-o onto a symlink to the model is refused too (exit 2)" test "$rc" -eq 2
check "the model is still unchanged" cmp -s main.tnet main.before
cd ../.. || exit 2

# --------------------------------------------------------------- absurd and constant data
cat >m.tnet <<'EOF2'
param G = 2 [W/K] range 0.1 .. 10
boundary room T = 20
node a C = 100 T0 = 20
conductance g a room G = G
heater h a P = 5
case c { duration = 1000; output = 100; data "huge.csv" }
EOF2
sed '6s/.*/400,1e300/' data.csv >huge.csv
run calibrate m.tnet --method lm
check "a measured 1e300 is refused by calibrate (exit 1)" test "$rc" -eq 1
check "at its row and column" grep -q "huge.csv:6:2: .*1e+300 is too large for a temperature of 'a'" err.txt
run diagnose m.tnet
check "and by diagnose (exit 1)" test "$rc" -eq 1
check "diagnose names row and column too" grep -q "huge.csv:6:2:" err.txt
sed 's/huge.csv/flat.csv/; s/P = 5/P = 0/' m.tnet >flat.tnet
awk -F, 'NR == 1 { print; next } { print $1 ",20.5" }' data.csv >flat.csv
run calibrate flat.tnet --method lm --json flat.json
check "constant data calibrate (exit 0)" test "$rc" -eq 0
check "R² is printed as undefined" grep -q "undefined" out.txt
check "no huge negative R²" bash -c "! grep -q 'e+2[0-9]\|-[0-9]\{6,\}' out.txt"
check "a note says why" grep -q "R² is undefined: every measured point has the same value" err.txt
check "JSON r2 is null" test "$(json flat.json "j['r2']")" = "None"
check "JSON notes say why" test "$(json flat.json "any('undefined' in n for n in j['notes'])")" = "True"
check "lm names the param without effect" grep -q "lm: param 'G' has no effect on the residuals" err.txt
check "no '#N' param number" bash -c "! grep -q 'param #' err.txt"
run diagnose flat.tnet --json flatd.json
check "diagnose on constant data runs (exit 0)" test "$rc" -eq 0
check "diagnose says R² is undefined" grep -q "R² undefined (every measured point has the same value" out.txt
check "diagnose JSON baseline r2 is null" test "$(json flatd.json "j['baseline']['r2']")" = "None"

# --------------------------------------------------------------- diagnose: paths, cases, boundaries
mkdir -p ev/model
printf 'case,event,start,end\n,lid,300,500\n' >ev/events.csv
sed 's/huge.csv/d.csv/' m.tnet >ev/model/m.tnet
cp data.csv ev/model/d.csv
cd ev/model || exit 2
run diagnose m.tnet --events ../events.csv
check "--events outside the model's folder is read (exit 0)" test "$rc" -eq 0
check "no model-folder refusal" bash -c "! grep -q 'own folder tree' err.txt"
run diagnose m.tnet --case nosuch
check "an unknown --case is a usage error (exit 2)" test "$rc" -eq 2
check "naming the case" grep -q "no case 'nosuch'" err.txt
cd ../.. || exit 2

cat >bo.tnet <<'EOF2'
boundary room T = 20
node a C = 100 T0 = 20
conductance g a room G = 1
heater h a P = 5
case c { duration = 1000; output = 100; data "room.csv" }
EOF2
awk -F, 'NR == 1 { print "time,room"; next } { print $1 ",20" }' data.csv >room.csv
run diagnose bo.tnet
check "data on a boundary only is an error (exit 1)" test "$rc" -eq 1
check "saying that no node is measured" grep -q "measures no node, only the boundary room" err.txt
check "and nothing on standard output" test ! -s out.txt
run diagnose bo.tnet --case c
check "also when the case is named (exit 1)" test "$rc" -eq 1
# A second case with node data: the boundary-only case is left out, the other diagnosed.
sed 's/^case c .*/&\ncase d { duration = 1000; output = 100; data "data.csv" }/' bo.tnet >two.tnet
run diagnose two.tnet
check "with another case measuring a node, diagnose runs (exit 0)" test "$rc" -eq 0
check "on that case only" grep -q "(1 case: d)" out.txt

cat >bt.tnet <<'EOF2'
boundary room T = table(data, "room")
node a C = 100 T0 = 20
conductance g a room G = 1
heater h a P = 5
case c { duration = 1000; output = 100; data "both.csv" }
EOF2
paste -d, data.csv <(awk -F, 'NR == 1 { print "room"; next } { print "20" }' data.csv) >both.csv
run diagnose bt.tnet
check "a measured boundary beside a node diagnoses (exit 0)" test "$rc" -eq 0
check "the exactly matched boundary is not among the worst nodes" bash -c "! grep -q '^  room ' out.txt"
check "no empty case name" bash -c "! grep -q '(case )' out.txt"
check "the node is listed" grep -q "^  a  *RMSE" out.txt

# --------------------------------------------------------------- bands of sensors
cat >s.tnet <<'EOF2'
param G = 1 [W/K] range 0.5 .. 2
boundary room T = 20
node a C = 100 T0 = 20
conductance g a room G = G
heater h a P = 5
sensor probe a offset = 0.5
case c { duration = 1000; output = 100 }
EOF2
run simulate s.tnet --samples 8 --sensors -o bands.csv
check "--samples --sensors runs (exit 0)" test "$rc" -eq 0
check "the bands include the sensor" grep -q "probe_min,probe_p5,probe_p50,probe_p95,probe_max" bands.csv
check "the sensor's band is the node's plus the offset" python3 - <<'EOF2'
import csv, sys
rows = list(csv.DictReader(open("bands.csv")))
ok = all(abs(float(r["probe_p50"]) - float(r["a_p50"]) - 0.5) < 1e-4 for r in rows)
sys.exit(0 if ok and len(rows) > 5 else 1)
EOF2
run simulate s.tnet --samples 8 --sensors --nodes probe --plot bands.svg -o /dev/null
check "--nodes selects the sensor for the plot (exit 0)" test "$rc" -eq 0
check "the plot draws its band" grep -q "probe min..max" bands.svg

finish
