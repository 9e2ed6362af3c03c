#!/usr/bin/env bash
# The command-line contract of `thermnet simulate`: output routing, header, --steady, --case,
# --duration, -o atomicity, --stats and lint failures. Usage: simulate_cli.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

# run CMD...: runs thermnet, stores stdout/stderr/exit status in out.txt/err.txt/$rc

# ----------------------------------------------------------------------------- models
cat >one.tnet <<'EOF'
model one
boundary amb T = 10
node hot C = 1000 T0 = 80
node arith C = 0
boundary wall T = pwl(0: 20, 50: 30)
node cold C = 500 T0 = 0
conductance g1 hot arith G = 4
conductance g2 arith amb G = 4
conductance g3 cold wall G = 2
conductance g4 hot cold G = 1
heater h hot P = 20
case warm { duration = 100; output = 10 }
EOF
cat >multi.tnet <<'EOF'
boundary amb T = 0
node n C = 100 T0 = 50
conductance g n amb G = 1
case first { duration = 100; output = 50 }
case second_case { duration = 30; output = 10 }
EOF
cat >lint_error.tnet <<'EOF'
boundary amb T = 0
node n C = 100
conductance g n nowhere G = 1
case c { duration = 10 }
EOF
cat >nocase.tnet <<'EOF'
boundary amb T = 0
node n C = 100 T0 = 50
conductance g n amb G = 1
EOF

# ----------------------------------------------------------------------------- checks
run simulate one.tnet
check "CSV goes to stdout without -o (exit 0, non-empty stdout)" test "$rc" -eq 0 -a -s out.txt
check "header is time + nodes and boundaries in declaration order" \
  test "$(head -1 out.txt)" = "time,amb,hot,arith,wall,cold"
check "11 rows at the output interval (0..100 by 10) plus header" test "$(wc -l <out.txt)" -eq 12
check "first data row starts at time 0 and boundaries are in degC" \
  bash -c "sed -n 2p out.txt | grep -Eq '^0,10\.0+,80\.0+,[0-9.]+,20\.0+,0\.0+$'"
check "last row is at the case duration 100" bash -c "tail -1 out.txt | grep -q '^100,'"
check "nothing on stderr for a clean run" test ! -s err.txt

run simulate one.tnet --steady
check "--steady exits 0" test "$rc" -eq 0
check "--steady writes the header and exactly one row" test "$(wc -l <out.txt)" -eq 2
check "--steady row is at time 0" bash -c "sed -n 2p out.txt | grep -q '^0,'"
# steady: hot loses 20 W through 2 W/K (series 4, 4) to amb and through 1 and 2 W/K in series
# (2/3 W/K) to wall (20 degC at t = 0): 20 = 2 (Th - 10) + (2/3)(Th - 20) -> Th = 20; arith = 15
check "--steady values: hot 20 degC, arith 15 degC (inputs at t = 0)" \
  /usr/bin/python3 -c "import csv,sys; r=list(csv.DictReader(open('out.txt')))[0]; sys.exit(abs(float(r['hot'])-20)>1e-6 or abs(float(r['arith'])-15)>1e-6)"

run simulate multi.tnet --case second_case
check "--case picks the named case (exit 0, ends at its duration 30)" \
  bash -c "test $rc -eq 0 && tail -1 out.txt | grep -q '^30,' && test \$(wc -l <out.txt) -eq 5"

run simulate multi.tnet --case nonesuch
check "unknown --case is a usage error (exit 2)" test "$rc" -eq 2
check "unknown --case names the case in the message" grep -q "nonesuch" err.txt
check "unknown --case writes nothing to stdout" test ! -s out.txt

run simulate multi.tnet
check "several cases and no --case is a usage error (exit 2)" test "$rc" -eq 2
check "several cases and no --case: the message lists the cases and asks for --case" \
  bash -c "grep -q -- '--case' err.txt && grep -q first err.txt && grep -q second_case err.txt"

run simulate one.tnet --duration 2h
check "--duration 2h exits 0" test "$rc" -eq 0
check "--duration 2h ends at 7200 s" bash -c "tail -1 out.txt | grep -q '^7200,'"

run simulate nocase.tnet --duration 45min
check "a model without cases runs with --duration 45min (ends at 2700)" \
  bash -c "test $rc -eq 0 && tail -1 out.txt | grep -q '^2700,'"
run simulate nocase.tnet
check "a model without cases and no --duration is a usage error (exit 2) asking for --duration" \
  bash -c "test $rc -eq 2 && grep -q -- '--duration' err.txt"

run simulate one.tnet --duration abc
check "--duration abc exits 2" test "$rc" -eq 2
check "--duration abc says what is wrong" grep -q "abc" err.txt

mkdir -p outdir
run simulate one.tnet -o missing_dir/result.csv
check "-o into a non-existent directory exits 2" test "$rc" -eq 2
check "-o into a non-existent directory creates nothing" \
  bash -c "test ! -e missing_dir && test -z \"\$(ls -A | grep -i tmp)\""

run simulate one.tnet -o outdir/good.csv
check "-o writes the file and exits 0" test "$rc" -eq 0 -a -s outdir/good.csv
check "-o leaves stdout empty" test ! -s out.txt
check "-o leaves no temporary file next to the output" \
  test "$(ls -A outdir)" = "good.csv"
cp outdir/good.csv good.ref

run simulate lint_error.tnet -o outdir/good.csv
check "a model with lint errors exits 1" test "$rc" -eq 1
check "a lint error is reported with its code" grep -q "unknown node 'nowhere'" err.txt
check "a failed run (lint error) leaves an existing -o file unchanged" cmp -s good.ref outdir/good.csv
run simulate one.tnet --case nonesuch -o outdir/good.csv
check "a failed run (unknown case) leaves an existing -o file unchanged" \
  bash -c "test $rc -eq 2 && cmp -s good.ref outdir/good.csv"
run simulate one.tnet --duration abc -o outdir/good.csv
check "a failed run (bad --duration) leaves an existing -o file unchanged" \
  bash -c "test $rc -eq 2 && cmp -s good.ref outdir/good.csv"
check "failed runs leave no temporary file" test "$(ls -A outdir)" = "good.csv"

run simulate lint_error.tnet -o outdir/new.csv
check "a model with lint errors writes no output file" test ! -e outdir/new.csv
run simulate lint_error.tnet
check "a model with lint errors writes nothing to stdout" test ! -s out.txt

run simulate one.tnet --stats
check "--stats exits 0" test "$rc" -eq 0
check "--stats prints solver statistics to stderr" grep -q "steps" err.txt
check "--stats keeps the CSV clean (header first, 12 lines, only numeric rows)" \
  bash -c "test \"\$(head -1 out.txt)\" = 'time,amb,hot,arith,wall,cold' && test \$(wc -l <out.txt) -eq 12 && ! tail -n +2 out.txt | grep -q '[a-zA-Z]'"
run simulate one.tnet --stats -o outdir/stats.csv
check "--stats with -o: the file equals the plain run's CSV" cmp -s good.ref outdir/stats.csv

finish
