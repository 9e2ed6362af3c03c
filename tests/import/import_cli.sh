#!/usr/bin/env bash
# `thermnet import` on bad input: every problem is an error at its file, line and column (or the
# file named), with exit status 1 for wrong content and 2 for a file that cannot be read or
# written, never a crash, a hang or a silent drop; parts not translated are listed, and fail the
# import unless --allow-partial. Usage: import_cli.sh PATH/TO/thermnet
. "$(dirname "$0")/../lib/harness.sh" "$@"

# timport ARGS...: `thermnet import` bounded by 120 s (nothing may hang it).
timport() { timeout 120 "$TN" import "$@" >out.txt 2>err.txt; rc=$?; }
# has TEXT: stderr holds TEXT (fixed string).
has() { grep -qF -- "$1" err.txt; }

control='HEADER CONTROL DATA, GLOBAL
      UID = SI, ABSZRO = -273.15'
good="$control
HEADER NODE DATA, MAIN
      1, 20.0, 100.0
     -2, 0.0, 0.0
HEADER CONDUCTOR DATA, MAIN
      1, 1, 2, 0.5"
printf '%s\n' "$good" >good.sin

timport good.sin -o good.tnet
check "a good deck imports (exit 0) and says what it wrote" \
  eval 'test "$rc" -eq 0 && has "1 node, 1 boundary, 1 link"'
run lint --werror good.tnet
check "  ... and the model lints clean" test "$rc" -eq 0
timport good.sin
check "without -o the model goes to standard output" \
  eval 'test "$rc" -eq 0 && grep -q "^conductance MAIN_G\[1\] MAIN\[1\] MAIN\[2\] G = 0.5" out.txt'

printf '%s\n      2, 1, 3, 0.5\n' "$good" >unknown.sin
timport unknown.sin
check "a conductor to a node no node data defines: located error, exit 1" \
  eval 'test "$rc" -eq 1 && has "unknown.sin:8:13: error: node MAIN.3 is defined by no node data [unknown-node]"'

printf '%s\n      2, 1, MAIN.1, 0.5\n' "$good" >self.sin
timport self.sin
check "a conductor from a node to itself: located error" \
  eval 'test "$rc" -eq 1 && has "self.sin:8:1: error: conductor 2 of submodel MAIN connects node MAIN.1 to itself [self-link]"'

printf '%s\n      3, 1, 2, -0.5\n' "$good" >negative.sin
timport negative.sin
check "a negative conductance: located at the value" \
  eval 'test "$rc" -eq 1 && has "negative.sin:8:16: error: conductor 3 of submodel MAIN has a negative conductance"'

for bad in "1.0E" "E5" "1.2.3" "0x10" "1.0+3" "1,5" "1.0D" "--1" "1e999"; do
  printf '%s\n      3, 20.0, %s\n' "$good" "$bad" | sed 's/^      3, /HEADER NODE DATA, MAIN\n      3, /' >fortran.sin
  timport fortran.sin
  if [ "$rc" -eq 1 ] && grep -q "fortran.sin:9:[0-9]*: error: .*\[bad-\(number\|syntax\)\]" err.txt; then
    ok "a number Fortran rejects ('$bad'): located error"
  else
    bad "a number Fortran rejects ('$bad'): located error" "$(head -c 600 err.txt)"
  fi
done
printf '%s\nHEADER NODE DATA, MAIN\n      3, +2.0D1, 1.E2\n      4, .5, 5.\n      5, -1.5d-1, 1Q2\n' \
  "$good" >fortran_ok.sin
timport fortran_ok.sin
check "numbers Fortran reads (+2.0D1, 1.E2, .5, 5., -1.5d-1, 1Q2) are read" \
  eval 'test "$rc" -eq 0 && grep -q "MAIN\[3\] C = 100 T0 = 20 " out.txt && grep -q "MAIN\[5\] C = 100 T0 = -0.15 " out.txt'

printf '%s\n      1, 20.0, 5.0\n' "$good" | sed 's/^      1, 20.0, 5.0$/HEADER NODE DATA, MAIN\n      1, 25.0, 5.0/' >dup.sin
timport dup.sin
check "a node defined twice: error with a note at the first definition" \
  eval 'test "$rc" -eq 1 && has "node MAIN.1 is defined twice" && has "dup.sin:4:1: note: first defined here"'

printf '%s\nHEADER NODE DATA, MAIN\n      5, -300.0, 1.0\n' "$good" >cold.sin
timport cold.sin
check "a temperature below absolute zero: located error" \
  eval 'test "$rc" -eq 1 && has "cold.sin:9:10: error: temperature -300 lies below absolute zero"'

printf '%s\nHEADER NODE DATA, MAIN\n      GEN 10, 1000000000, 1, 20.0, 1.0\n' "$good" >gen.sin
timport gen.sin
check "GEN of 10^9 nodes: refused before generating (too-large)" \
  eval 'test "$rc" -eq 1 && has "[too-large]"'

printf '%s\nHEADER CONDUCTOR DATA, MAIN\n     -5, 1, 2, 0.01\n' "$good" >nosigma.sin
timport nosigma.sin
check "a radiation conductor without SIGMA: error saying what to add" \
  eval 'test "$rc" -eq 1 && has "needs SIGMA in HEADER CONTROL DATA, GLOBAL"'

# DOS end-of-file marks (0x1a, which the reader admits as text) inside control and option lines
# are blanks there as in every other block: the deck imports and the title is written without them.
printf 'HEADER CONTROL DATA, GLOBAL\n      UID = SI,\x1a ABSZRO = -273.15\x1a\nHEADER OPTIONS DATA\n\x1aTITLE\x1a A BOX\x1a\nHEADER NODE DATA, MAIN\n      1, 20.0, 100.0\n     -2, 0.0, 0.0\nHEADER CONDUCTOR DATA, MAIN\n      1, 1, 2, 0.5\n' >ctrlz.sin
timport ctrlz.sin -o ctrlz.tnet
check "0x1a marks in control and option lines: imported, the title written clean" \
  eval 'test "$rc" -eq 0 && grep -qx "# TITLE A BOX" ctrlz.tnet && ! grep -q $'"'"'\x1a'"'"' ctrlz.tnet'

# Untranslated parts: listed with file and line; the import fails unless --allow-partial.
printf '%s\nHEADER ARRAY DATA, MAIN\n      10 = 0.0, 1.0\n      20.0, 2.0\n      END\nHEADER VARIABLES 0, MAIN\n      MAIN.Q1 = MAIN.Q1 + 4.0\n      IF (TIMEN .GT. 10.0) MAIN.Q1 = 0.0\nF     X = 1.0\nHEADER FLOW DATA, LOOP, FID = 717\n      LU DEF, TLENT = 70.0\nHEADER CONDUCTOR DATA, MAIN\n      SIV 7, 1, 2, 10, 0.5\n' \
  "$good" >partial.sin
timport partial.sin -o partial.tnet
check "untranslated blocks and logic: each listed with file and line, exit 1, nothing written" \
  eval 'test "$rc" -eq 1 && ! test -e partial.tnet &&
        has "partial.sin:9:1: warning: not translated: HEADER ARRAY DATA, MAIN, lines 9-11" &&
        has "partial.sin:14:1: warning: not translated: HEADER VARIABLES 0, MAIN, lines 14-15: user logic" &&
        has "partial.sin:17:1: warning: not translated: HEADER FLOW DATA, LOOP, line 17" &&
        has "partial.sin:19:1: warning: not translated: HEADER CONDUCTOR DATA, MAIN, line 19: conductor data with the option SIV" &&
        has "--allow-partial"'
timport partial.sin -o partial.tnet --allow-partial
check "  ... with --allow-partial: written, every part still listed, and in the model's heading" \
  eval 'test "$rc" -eq 0 && grep -q "^# not translated: partial.sin:14: HEADER VARIABLES 0, MAIN, lines 14-15: user logic" partial.tnet &&
        grep -q "^heater MAIN_Q\[1\] MAIN\[1\] P = 4 " partial.tnet && has "4 parts not translated"'
run lint --werror partial.tnet
check "  ... and the partial model lints clean" test "$rc" -eq 0

# INSERT: relative to the deck; missing, binary, cyclic, too deep, outside the folder.
mkdir -p deck/sub outside
printf '%s\nINSERT sub/more.cc\n' "$good" >deck/main.sin
printf 'HEADER CONDUCTOR DATA, MAIN\n      9, 1, 2, 0.25\n' >deck/sub/more.cc
timport deck/main.sin
check "INSERT of a file relative to the deck" eval 'test "$rc" -eq 0 && grep -q "MAIN_G\[9\].*deck/sub/more.cc:2" out.txt'
printf '%s\nINSERT nothere.cc\n' "$good" >deck/missing.sin
timport deck/missing.sin
check "INSERT of a missing file: error naming it, exit 2" \
  eval 'test "$rc" -eq 2 && has "missing.sin:8:1: error: cannot include '"'"'deck/nothere.cc'"'"'"'
head -c 2000 /dev/urandom >deck/blob.cc
printf 'HEADER CONDUCTOR DATA, MAIN\n\0\0\0\1\2\n' >>deck/blob.cc
printf '%s\nINSERT blob.cc\n' "$good" >deck/binary.sin
timport deck/binary.sin
check "INSERT of a binary file: error naming it (binary), exit 1" \
  eval 'test "$rc" -eq 1 && has "cannot include '"'"'deck/blob.cc'"'"': it is a binary file"'
printf '%s\nINSERT b.cc\n' "$good" >deck/cycle.sin
printf 'INSERT c.cc\n' >deck/b.cc
printf 'INSERT b.cc\n' >deck/c.cc
timport deck/cycle.sin
check "an INSERT cycle: located error naming the cycle" \
  eval 'test "$rc" -eq 1 && has "c.cc:1:1: error: including '"'"'b.cc'"'"' again forms a cycle: b.cc -> c.cc -> b.cc"'
for i in $(seq 1 70); do printf 'INSERT d%d.cc\n' $((i + 1)) >deck/d$i.cc; done
printf 'C end\n' >deck/d71.cc
printf '%s\nINSERT d1.cc\n' "$good" >deck/deep.sin
timport deck/deep.sin
check "INSERTs nested 70 deep: refused at depth 64 (include-too-deep)" \
  eval 'test "$rc" -eq 1 && has "nested more than 64 deep [include-too-deep]"'
printf 'HEADER CONDUCTOR DATA, MAIN\n      9, 1, 2, 0.25\n' >outside/far.cc
ln -s ../outside/far.cc deck/link.cc
printf '%s\nINSERT link.cc\n' "$good" >deck/symlink.sin
timport deck/symlink.sin
check "INSERT of a symlink to a file outside the deck's folder: refused (exit 2)" \
  eval 'test "$rc" -eq 2 && has "outside the model'"'"'s folder"'
timport --allow-outside-paths deck/symlink.sin
check "  ... allowed with --allow-outside-paths" test "$rc" -eq 0
printf '%s\nINSERT ../outside/far.cc\n' "$good" >deck/updir.sin
timport deck/updir.sin
check "INSERT ../outside: refused (exit 2)" eval 'test "$rc" -eq 2'

printf 'HEADER NODE DATA, MAIN\n\0binary\n' >binary.sin
timport binary.sin
check "a binary file on the command line: refused naming it" \
  eval 'test "$rc" -eq 1 && has "binary.sin" && has "binary file"'
timport nothere.sin
check "a missing file on the command line: exit 2" eval 'test "$rc" -eq 2 && has "nothere.sin"'
mkfifo pipe.sin
timport pipe.sin
check "a FIFO: refused at once (exit 2)" eval 'test "$rc" -eq 2 && has "FIFO"'
printf 'just some words\nand more\n' >prose.txt
timport prose.txt
check "a file of no known format: error saying to give --format" \
  eval 'test "$rc" -eq 1 && has "give --format sinda or --format spice"'

# Outputs: never the input, never a directory.
timport good.sin -o good.sin
check "-o onto the input: refused, the input intact (exit 2)" \
  eval 'test "$rc" -eq 2 && grep -q "HEADER NODE DATA" good.sin'
timport deck/main.sin -o deck/sub/more.cc
check "-o onto an INSERTed file: refused (exit 2)" eval 'test "$rc" -eq 2 && grep -q "HEADER" deck/sub/more.cc'
mkdir -p adir
timport good.sin -o adir
check "-o a directory: refused (exit 2)" eval 'test "$rc" -eq 2'
ln -s good.tnet alias.tnet
timport good.sin -o alias.tnet
check "-o through a symlink the user named: written to its target" \
  eval 'test "$rc" -eq 0 && test -L alias.tnet && grep -q "^model good" good.tnet'

# A 10^6-line deck: imported in bounded time and memory, every node written.
python3 - <<'PY' >big.sin
print("HEADER CONTROL DATA, GLOBAL\n      UID = SI, ABSZRO = -273.15")
print("HEADER NODE DATA, BIG")
print("     -1, 0.0, 0.0")
n = 499_998
for i in range(2, n + 2):
    print(f"      {i}, 20.0, {1 + i % 7}.0")
print("HEADER CONDUCTOR DATA, BIG")
for i in range(1, n + 1):
    print(f"      {i}, {i}, {i + 1}, 0.{1 + i % 9}")
PY
lines=$(wc -l <big.sin)
timport big.sin -o big.tnet
check "a $lines-line deck: imported (exit 0)" eval 'test "$rc" -eq 0 && has "499998 nodes, 1 boundary, 499998 links"'
run lint big.tnet
check "  ... and the model it writes lints" test "$rc" -eq 0

# SPICE: bad input.
printf '* t\nR1 a 0 1k\nC1 a 0 -5\nI1 0 a 1\n.end\n' >negcap.cir
timport negcap.cir
check "SPICE: a negative capacitance: located error" \
  eval 'test "$rc" -eq 1 && has "negcap.cir:3:8: error: '"'"'c1'"'"' has a negative capacitance"'
printf '* t\nR1 a b 1k\nC1 a b 5\nR2 b 0 1\nC2 b c 1\nR3 c 0 2\nI1 0 a 1\n.end\n' >nochain.cir
timport nochain.cir
check "SPICE: a capacitor between nodes outside any Foster chain: refused with the reason" \
  eval 'test "$rc" -eq 1 && has "[foster-chain]"'
printf '* t\nR1 a 0 {rx * 2}\nI1 0 a 1\n.end\n' >param.cir
timport param.cir
check "SPICE: an unknown parameter: located in the expression" \
  eval 'test "$rc" -eq 1 && has "param.cir:2:9: error: no parameter is called '"'"'rx'"'"'"'
printf '* t\n.param a = {b + 1}\n.param b = {a * 2}\nR1 n 0 {a}\nI1 0 n 1\n.end\n' >cycle.cir
timport cycle.cir
check "SPICE: parameters that depend on each other: error, no hang" \
  eval 'test "$rc" -eq 1 && has "[param-cycle]"'
printf '* t\n.subckt s a\nX1 a s\n.ends\nX1 n s\nR1 n 0 1\nI1 0 n 1\n.end\n' >recurse.cir
timport recurse.cir
check "SPICE: a subcircuit that contains itself: error" \
  eval 'test "$rc" -eq 1 && has "[subckt-cycle]"'
printf '* t\nR1 n 0 1\nL1 n 0 1m\nI1 0 n PULSE(0 1 0 1n 1n 1 2)\n.end\n' >kinds.cir
timport kinds.cir
check "SPICE: an inductor and a PULSE source: listed as not translated, exit 1" \
  eval 'test "$rc" -eq 1 && has "kinds.cir:3:1: warning: not translated: an inductor" && has "kinds.cir:4:8: warning: not translated: the pulse waveform"'
python3 - <<'PY' >nest.cir
print("* 70 subcircuits, each holding the next")
for k in range(70):
    print(f".subckt s{k} a\nX1 a s{k + 1}\n.ends")
print(".subckt s70 a\nR1 a 0 1\n.ends\nX0 n s0\nI1 0 n 1\n.end")
PY
timport nest.cir
check "SPICE: instances nested 70 deep: refused at 64 (subckt-too-deep)" \
  eval 'test "$rc" -eq 1 && has "[subckt-too-deep]"'
mkfifo deck/pipe.cc
printf '%s\nINSERT pipe.cc\n' "$good" >deck/fifo.sin
timport deck/fifo.sin
check "INSERT of a FIFO: refused at once (exit 2)" eval 'test "$rc" -eq 2 && has "FIFO"'
printf '* t\nR1 a 0 1\nC1 a 0 1\nI1 0 a 1\n.tran 1u 10\n.end\n' >rows.cir
timport rows.cir
check "SPICE: a TSTEP giving 10^7 rows: the case writes 100,000, with a note" \
  eval 'test "$rc" -eq 0 && grep -q "^  output = 0.0001$" out.txt && has "would write 10000000 rows"'
printf '* t\n.include loop.inc\n.end\n' >inc.cir
printf '.include inc2.inc\n' >loop.inc
printf '.include loop.inc\n' >inc2.inc
timport inc.cir --format spice
check "SPICE: an include cycle: located error" eval 'test "$rc" -eq 1 && has "[include-cycle]"'
printf '* t\nR1 n 0 1\nI1 0 n 1\n' >one.cir
timport one.cir --format sinda
check "--format sinda on a netlist: errors, no crash" eval 'test "$rc" -eq 1'
# The examples of docs/import.md import and lint clean.
examples="$HERE/../../models/import"
timport "$examples/camera.sin" -o camera.tnet
check "docs example camera.sin imports (7 nodes, 2 boundaries, 13 links, 2 heaters)" \
  eval 'test "$rc" -eq 0 && has "7 nodes, 2 boundaries, 13 links, 2 heaters"'
run lint --werror camera.tnet
check "  ... and lints clean" test "$rc" -eq 0
timport "$examples/igbt.cir" -o igbt.tnet
check "docs example igbt.cir imports, its Foster network as a Cauer ladder" \
  eval 'test "$rc" -eq 0 && has "equivalent Cauer ladder j, cauer_j[1 .. 2]"'
run lint --werror igbt.tnet
check "  ... and lints clean" test "$rc" -eq 0
# A node with a capacity cites the card that gives it, not the first card that names it.
printf '* boards\nV1 amb 0 20\nRch chassis amb 0.5\nCch chassis 0 1200\nR1 b1 chassis 2\nC1 b1 0 50\nI1 0 b1 10\n.tran 1 100\n.end\n' >cites.cir
run import cites.cir -o cites.tnet
check "import: a node's comment cites its capacitor card" \
  eval 'test "$rc" -eq 0 && grep -q "^node chassis C = 1200 .*# cites.cir:4$" cites.tnet && grep -q "^node b1 C = 50 .*# cites.cir:6$" cites.tnet'

# A floating part (no path of links to a boundary: no DC path to ground) is named, at its line.
printf '* t\nR1 a 0 1\nR2 b c 1\nI1 0 a 1\n.end\n' >floating.cir
run import floating.cir -o floating.tnet
check "import: a floating part is named at its line (exit 0, the model written)" \
  eval 'test "$rc" -eq 0 && grep -q "floating.cir:3:1: note: node b has no path of links to a boundary" err.txt && grep -q "node c has no path" err.txt && ! grep -q "node a has no path" err.txt && test -s floating.tnet'

# An empty output name is refused, not taken as standard output.
run import cites.cir -o ''
check "import -o '': exit 2, an output needs a file name" \
  eval 'test "$rc" -eq 2 && grep -q "needs a file name" err.txt && ! grep -q "^model" out.txt'

# SPICE subcircuits: hostile definitions and instances.
printf '* t\n.subckt spare a\nR1 a 0 1\n.ends\nR1 n 0 1\nI1 0 n 1\n.end\n' >unused.cir
run import unused.cir -o unused.tnet
check "SPICE: a subcircuit never instantiated: not written, with a note at its line" \
  eval 'test "$rc" -eq 0 && has "unused.cir:2:1: note: subcircuit '"'"'spare'"'"' is never instantiated: not written" && ! grep -q "submodel" unused.tnet'
run lint --werror unused.tnet
check "  ... and the model lints clean" test "$rc" -eq 0
printf '* t\n.subckt a n\nX1 n b\n.ends\n.subckt b n\nX1 n a\n.ends\nX1 m a\nR1 m 0 1\nI1 0 m 1\n.end\n' >mutual.cir
timport mutual.cir
check "SPICE: two subcircuits that contain each other: [subckt-cycle], nothing written" \
  eval 'test "$rc" -eq 1 && has "[subckt-cycle]" && test ! -s out.txt'
printf '* t\n.subckt s a r=1\nR1 a 0 {r}\n.ends\nX1 n s q=2\nI1 0 n 1\n.end\n' >badkey.cir
timport badkey.cir
check "SPICE: an instance parameter the subcircuit lacks: error at file:line:column" \
  eval 'test "$rc" -eq 1 && has "badkey.cir:5:10: error: subcircuit '"'"'s'"'"' has no parameter '"'"'q'"'"' (its parameters: r) [unknown-param]"'
printf '* t\n.subckt s a\nR1 a 0 1\n.ends\nX1 n m s\nI1 0 n 1\n.end\n' >nodes.cir
timport nodes.cir
check "SPICE: an instance with the wrong number of nodes: error at its line" \
  eval 'test "$rc" -eq 1 && has "nodes.cir:5:1: error: subcircuit '"'"'s'"'"' has 1 node, the instance gives 2"'
python3 - <<'PY' >deep64.cir
print("* 64 subcircuits, each holding the next: as deep as thermnet's submodels may nest")
for k in range(63):
    print(f".subckt s{k} a\nX1 a s{k + 1}\nR{k} a 0 {k + 1}\n.ends")
print(".subckt s63 a\nR1 a 0 1\n.ends\nX0 n s0\nI1 0 n 1\n.end")
PY
run import deep64.cir -o deep64.tnet
check "SPICE: instances nested 64 deep: 64 nested submodels" \
  eval 'test "$rc" -eq 0 && test "$(grep -c "^ *submodel s" deep64.tnet)" -eq 64'
run lint --werror deep64.tnet
check "  ... and the model lints clean" test "$rc" -eq 0
# Subcircuit names that are no thermnet names, or are keywords or element kinds: renamed, noted.
for name in node case for a.b 1abc resistor heater gnd; do
  printf '* t\n.subckt %s a b\nR1 a b 2\nR2 a 0 1\n.ends\nX1 n k %s\nX2 m n %s\nRk k 0 1\nI1 0 m 1\n.end\n' \
    "$name" "$name" "$name" >named.cir
  run import named.cir -o named.tnet
  if [ "$rc" -eq 0 ] && grep -q "note: subcircuit '$name' is written as submodel" err.txt &&
    grep -q "^submodel [A-Za-z_][A-Za-z0-9_]*(a, b, gnd) {" named.tnet &&
    "$TN" lint --werror named.tnet >/dev/null 2>&1; then
    ok "SPICE: a subcircuit named '$name': renamed with a note, the model lints clean"
  else
    bad "SPICE: a subcircuit named '$name': renamed with a note, the model lints clean" \
      "$(head -c 600 err.txt; grep submodel named.tnet)"
  fi
done

# Numbers below the smallest double: located errors, not a capacity or conductance of 0.
printf '* t\nR1 a 0 1\nC1 a 0 1e-400\nI1 0 a 1\n.end\n' >tiny.cir
timport tiny.cir
check "SPICE: a capacitance of 1e-400: located error (underflows), nothing written" \
  eval 'test "$rc" -eq 1 && has "tiny.cir:3:8: error: '"'"'1e-400'"'"' underflows" && test ! -s out.txt'
printf '* t\nR1 a 0 {1e-200 * 1e-200}\nI1 0 a 1\n.end\n' >tinyx.cir
timport tinyx.cir
check "SPICE: a resistance whose expression underflows: located error" \
  eval 'test "$rc" -eq 1 && has "tinyx.cir:2:9: error: the expression'"'"'s value underflows"'
printf '%s\nHEADER NODE DATA, MAIN\n      3, 20.0, 1.0D-400\n' "$good" >tiny.sin
timport tiny.sin
check "SINDA: a capacity of 1.0D-400: located error (underflows)" \
  eval 'test "$rc" -eq 1 && has "tiny.sin:9:16: error: '"'"'1.0D-400'"'"' underflows"'

# A deck without units: the note says where (the control data that lacks them, else the first block).
printf 'HEADER CONTROL DATA, GLOBAL\n      TIMEND = 10\nHEADER NODE DATA, MAIN\n      1, 20.0, 1.0\n     -2, 0.0, 0.0\nHEADER CONDUCTOR DATA, MAIN\n      1, 1, 2, 0.5\n' >nounits.sin
timport nounits.sin -o nounits.tnet
check "SINDA: a deck stating no units: the note names the CONTROL DATA line" \
  eval 'test "$rc" -eq 0 && has "nounits.sin:1:1: note: the deck states no units" && grep -q "^# note: nounits.sin:1: the deck states no units" nounits.tnet'

finish
