# Hostile inputs to loops, submodels, cases and the commands that run models (issue 31), sourced by
# run.sh inside its temporary folder: each ends in a located error or a clean run within seconds and
# a bounded address space, never in a crash, a hang or a silent wrong answer.

# Recursion: a for header with 20,000 variables (in the model and in a case), a chain of 30,000
# submodels each instantiating the next.
python3 - >vars.tnet <<'EOF'
n = 20000
header = ", ".join("w%d in 1 .. 1" % k for k in range(n))
print("boundary b T = 20")
print("for %s {\n  node q[w0 + w%d] C = 1\n  conductance g[w0] q[w0 + w%d] b G = 1\n}" % (header, n - 1, n - 1))
print("case c {\n  duration = 1\n  for %s { q[w0 + w%d].C = 2 }\n}" % (header, n - 1))
EOF
hostile_run "a for header with 20,000 variables, in the model and in a case" 30 1000 0 "" lint vars.tnet

python3 - >chain.tnet <<'EOF'
n = 30000
print("boundary b T = 20")
for k in range(n - 1):
    print("submodel s%d(x) {\n  s%d inner x\n}" % (k, k + 1))
print("submodel s%d(x) {\n  node m C = 1\n  conductance g m x G = 1\n}" % (n - 1))
print("s0 top b")
EOF
hostile_run "a chain of 30,000 submodels, each instantiating the next" 30 1000 1 \
  "instances more than 64 deep \[submodel-too-deep\]" lint chain.tnet

# Chains of values each read by the next (issue 51: 10,000 chained consts or params crashed lint
# and the language server, the evaluation recursing as deep as the chain): evaluated in a loop, and
# right (the boundary at c99999 / 1000 = 100 degC); a cycle as long is one located error.
python3 - >consts.tnet <<'EOF'
n = 100000
print("const c0 = 1")
for k in range(1, n):
    print("const c%d = c%d + 1" % (k, k - 1))
print("boundary b T = c%d / 1000\nnode m C = 1\nconductance g m b G = 1\ncase c { duration = 1 }" % (n - 1))
EOF
hostile_run "a chain of 100,000 consts: simulate --steady reads b = 100 degC" 60 2000 0 \
  "^0,100.00000000,100.00000000" simulate consts.tnet --steady
sed 's/^const /param /' consts.tnet >params.tnet
hostile_run "a chain of 100,000 params" 60 2000 0 "^0,100.00000000" simulate params.tnet --steady
sed 's/^const c0 = 1$/const c0 = c99999 + 1/' consts.tnet >cycle.tnet
hostile_run "a cycle of 100,000 consts: one located cycle error" 60 2000 1 \
  "'c[0-9]*' depends on itself: c[0-9]* -> c[0-9]* -> .*\[cycle\]" lint cycle.tnet

printf 'boundary b T = 20\nsubmodel s(x) {\n  node m C = 1\n  conductance g m x G = 1\n  s inner m\n}\n' >selfsub.tnet
hostile_run "a submodel containing itself, never instantiated" 20 1000 1 \
  "submodel 's' contains itself: s -> s \[submodel-cycle\]" lint selfsub.tnet

# Caps counted before the work: a billion iterations, 19 million nodes, 10^10 iterations of nested
# loops, in the model and in a case.
printf 'for i in 1 .. 1000000000 { }\n' >billion.tnet
hostile_run "a loop of 1,000,000,000 empty iterations" 20 1000 1 "too-large" lint billion.tnet
printf 'node p[1 .. 19000000] C = 1\n' >nineteen.tnet
hostile_run "19,000,000 nodes from one range" 20 1000 1 "too-large" lint nineteen.tnet
printf 'boundary b T = 20\nfor i in 1 .. 100000 {\n  for j in 1 .. 100000 { node p[i, j] C = 1 }\n}\n' >nested.tnet
# They stop at the limit after 5,000,000 declarations and iterations: 3-4 s of CPU, a minute of
# wall time on a loaded 2-core machine.
hostile_run "nested loops of 10^10 iterations" 300 2000 1 "too-large" lint nested.tnet
printf 'boundary b T = 20\nnode n C = 1\nconductance g n b G = 1\ncase c {\n  duration = 1\n  for i in 1 .. 100000, j in 1 .. 100000 { }\n}\n' >caseloop.tnet
hostile_run "a case loop of 10^10 iterations" 30 1000 1 "at most 1000000 times" lint caseloop.tnet

# A wrong bound inside 22 nested loops, in the model and in a case: reported once, and the loop is
# not evaluated again in the 2 million iterations around it (the fuzzer found a case taking 6 s).
python3 -c "
outer = ''.join(f'for a{k} in 1 .. 2 {{\n' for k in range(21))
print('node n C = 1\n' + outer + 'for z in 1 [q] .. 2 { node m[z] C = 1 }\n' + '}\n' * 21)
" >badbound.tnet
hostile_run "a wrong loop bound inside 22 nested loops" 20 1000 1 \
  "badbound.tnet:23:1: error: unknown unit 'q'" lint badbound.tnet
python3 -c "
outer = ''.join(f'for a{k} in 1 .. 2 {{\n' for k in range(21))
print('node n C = 1\ncase c {\n  duration = 1\n' + outer + 'for z in 1 [q] .. 2 { n.C = z }\n'
      + '}\n' * 22)
" >casebound.tnet
hostile_run "  ... in a case" 20 1000 1 "casebound.tnet:25:10: error: unknown unit 'q'" lint casebound.tnet

# One warning per statement, not one per node: 400,000 isolated nodes from a range and a loop.
printf 'boundary b T = 20\nnode p[1 .. 200000] C = 1\nfor i in 1 .. 200000 { node q[i] C = 1 }\n' >isolated.tnet
hostile_run "400,000 isolated generated nodes" 60 2000 0 \
  "nodes 'q\[1\]', 'q\[2\]', 'q\[3\]', 'q\[4\]' and 199996 more have no links" lint isolated.tnet
if [ "$(timeout 60 "$bin" lint isolated.tnet 2>&1 | grep -c 'isolated-node')" = 2 ]; then
  echo "ok: ... in exactly two isolated-node warnings"
  passed=$((passed + 1))
else
  fail "400,000 isolated generated nodes: not exactly two isolated-node warnings"
fi

# An index too large to be exact.
printf 'node p[9007199254740992] C = 1\n' >bigindex.tnet
hostile_run "an index of 2^53" 20 1000 1 "must lie between -1e15 and 1e15, got 9.0072e\+15" \
  lint bigindex.tnet

# A case that sets one key twice, directly and from a loop.
cat >twice.tnet <<'EOF'
boundary b T = 20
node n[1 .. 2] C = 1
conductance g[1 .. 2] n[1 .. 2] b G = 1
heater h n[1] P = 1
case c {
  duration = 1
  h.P = 2
  h.P = 3
  for i in 1 .. 2 { n[1].C = i }
}
EOF
hostile_run "a case setting h.P twice" 20 1000 1 "twice.tnet:8:3: error: case 'c' sets 'h.P' twice" \
  lint twice.tnet
hostile_run "a case loop setting n[1].C in two iterations" 20 1000 1 "case 'c' sets 'n\[1\].C' twice" \
  lint twice.tnet

# A thermostat heating and sensing a node without heat capacity, whose reading jumps past its other
# threshold at each switch, has no consistent state: the run fails naming it and the time, at the
# start or when it becomes so (here when the boundary, warming, makes the heated state too hot).
printf 'boundary amb T = 0\nnode a C = 0\nconductance g a amb G = 1\nthermostat th a P = 30 on = 10 off = 20\ncase c { duration = 100 }\n' >massless_tstat.tnet
hostile_run "a thermostat on a node without capacity, no consistent state at the start" 20 1000 1 \
  "at t = 0 s.*events keep firing.*thermostat 'th'" simulate massless_tstat.tnet
printf 'boundary amb T = pwl(0: 0, 100: 10)\nnode a C = 0\nconductance g a amb G = 1\nthermostat th a P = 15 on = 10 off = 20\ncase c { duration = 100 }\n' >massless_ramp.tnet
hostile_run "  ... and none from t = 50 s on" 20 1000 1 "at t = 50.* s.*events keep firing.*thermostat 'th'" \
  simulate massless_ramp.tnet

# A listed output time after the end of the case is located at lint.
printf 'boundary b T = 20\nnode n C = 1\nconductance g n b G = 1\ncase c {\n  duration = 100\n  output = 10, 50, 150\n}\n' >late_output.tnet
hostile_run "an output time after the duration" 20 1000 1 \
  "late_output.tnet:6:3: error: a time of 'output' of case 'c' must be at most the case's duration \(100 s\), got 150 s" \
  lint late_output.tnet

# The per-node reports of a 100,000-node chain: the energy balance of a transient and the heat
# flows of a steady state are one pass over the elements (each scanned all elements per node, and
# the energy account asked every element whether it switches by scanning all of them: --energy
# was stopped after 5 minutes; now 1-3 s each).
printf 'boundary amb T = 20 [degC]\nnode p[1 .. 100000] C = 10 [J/K] T0 = 20 [degC]\nfor i in 1 .. 99999 { conductance g[i] p[i] p[i + 1] G = 0.5 }\nconductance out p[100000] amb G = 1\nheater h p[1] P = 5 [W]\ncase c { duration = 100 [s] }\n' >chain.tnet
hostile_run "simulate --energy of a 100,000-node chain" 120 2000 0 "" \
  simulate chain.tnet --output 50 -o chain.csv --energy chain_energy.txt
hostile_run "simulate --steady --flows of a 100,000-node chain" 120 2000 0 "" \
  simulate chain.tnet --steady -o chain_steady.csv --flows chain_flows.txt

# Command lines.
printf 'boundary b T = 20\nnode n C = 100\nconductance k n b G = 1\nparam G = 1\nheater h n P = G\ncase c { duration = 10 }\n' >swept.tnet
hostile_run "sweep: two axes of 100,000 values" 20 1000 2 "the grid has 100000 x 100000 points" \
  sweep swept.tnet --param G=0.5..1.5:100000 --param h.P=1..2:100000
hostile_run "sweep: one param swept twice" 20 1000 2 "param 'G' is given more than once" \
  sweep swept.tnet --param G=0.5..1.5:3 --param G=1
hostile_run "--set: an expression is not a number" 20 1000 2 \
  "'2\*3' is not a number.*expressions are not evaluated" simulate swept.tnet --set G=2*3
hostile_run "--set: one param set twice" 20 1000 2 "param 'G' is given more than once" \
  simulate swept.tnet --set G=1 --set G=2
printf 'boundary b T = 20\nnode n C = 100\nconductance k n b G = 1\nparam P = 1 range 0 .. 5\nheater h n P = P\ncase c { duration = 10 }\ncase d { duration = 10 }\nrequire band "n" 0 .. 100 [degC]\n' >cases.tnet
hostile_run "check --case d,d" 20 1000 2 "case 'd' is given twice" check cases.tnet --case d,d
hostile_run "design --case c,c,d" 20 1000 2 "case 'c' is given twice" \
  design cases.tnet --case c,c,d

python3 - >events.csv <<'EOF'
print("case,event,start,end")
for k in range(120000):
    print("c,e%d,%d,%d" % (k % 7, 10 * k, 10 * k + 5))
print("c,e0,5,x")
EOF
hostile_run "diagnose --events: 120,000 rows, a bad last cell" 30 1000 1 \
  "events.csv:120002:4: 'x' is not a time" diagnose cases.tnet --events events.csv
printf '\xef\xbb\xbfcase,start,end\nc,0,5\n' >bom_events.csv
if timeout 60 "$bin" diagnose cases.tnet --events bom_events.csv 2>&1 | grep -q "unknown column"; then
  fail "diagnose --events: a byte order mark is read as part of the first column"
else
  echo "ok: diagnose --events: a byte order mark is skipped"
  passed=$((passed + 1))
fi
