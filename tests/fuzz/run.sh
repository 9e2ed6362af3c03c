#!/usr/bin/env bash
# Builds a libFuzzer target with clang++-14 (ASan + UBSan) and runs it for a bounded time.
#
#   FUZZ_TARGET=csv run.sh        # the target: parser (default, fuzz_parser.cpp) or csv
#   FUZZ_SECONDS=60 run.sh        # default 60 s
#   FUZZ_BUILD_DIR=DIR run.sh     # keep objects and the corpus in DIR (default: a temp folder)
#   run.sh CRASH_FILE...          # replay reproducers instead of fuzzing
#
# The corpus is seeded from tests/golden and models/ (*.tnet, or *.csv up to 64 KB for csv), and
# with the forms of recorded campaigns (signal expressions, table options, data statements with
# column maps, sensors, per-case start temperatures; CSV files with their separators, UNIX and ISO
# time columns and on/off words) and deeply nested signals.
# Exits non-zero on a crash,
# a sanitizer report, a timeout or an out-of-memory, and prints the reproducer.
set -u

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
seconds=${FUZZ_SECONDS:-60}
target=${FUZZ_TARGET:-parser}
cxx=${FUZZ_CXX:-clang++-14}

if ! command -v "$cxx" >/dev/null; then
  echo "fuzz: $cxx not found (install clang-14 and libclang-rt-14-dev)" >&2
  exit 1
fi

if [ -n "${FUZZ_BUILD_DIR:-}" ]; then
  work=$FUZZ_BUILD_DIR/$target
  mkdir -p "$work"
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi

flags=(-std=c++20 -O1 -g -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined
  -fno-omit-frame-pointer -I"$root" -DTHERMNET_VERSION=\"fuzz\")
case "$target" in
parser)
  sources=("$root"/lang/*.cpp "$root"/kernel/core/element_registry.cpp "$root"/kernel/core/linear_link.cpp
    "$root"/plugins/element/*.cpp "$here"/fuzz_parser.cpp)
  ;;
csv)
  sources=("$root"/lang/csv.cpp "$root"/lang/source.cpp "$root"/lang/display_text.cpp
    "$root"/lang/path_policy.cpp "$root"/lang/units.cpp "$root"/lang/diagnostics.cpp
    "$here"/fuzz_csv.cpp)
  ;;
*)
  echo "fuzz: unknown FUZZ_TARGET '$target' (parser or csv)" >&2
  exit 2
  ;;
esac

# Compile each source into its own object (two at a time; the X3 grammar is slow to compile),
# skipping objects newer than their source and every header; through ccache when it is installed.
launcher=$(command -v ccache || true)
newest_header=$(find "$root/lang" "$root/kernel" -name '*.hpp' -o -name '*.def' | xargs ls -t | head -1)
objects=()
pids=()
for src in "${sources[@]}"; do
  obj="$work/obj/$(realpath --relative-to="$root" "$src" | tr / _).o"
  objects+=("$obj")
  if [ -f "$obj" ] && [ "$obj" -nt "$src" ] && [ "$obj" -nt "$newest_header" ]; then continue; fi
  mkdir -p "$work/obj"
  # The parser target copies the project's data files into its model's folder (fuzz_parser.cpp).
  extra=()
  [ "$src" = "$here/fuzz_parser.cpp" ] && extra=(-DTHERMNET_FUZZ_ROOT="\"$root\"")
  $launcher "$cxx" "${flags[@]}" "${extra[@]}" -c "$src" -o "$obj" &
  pids+=($!)
  if [ "${#pids[@]}" -ge 2 ]; then
    wait "${pids[0]}" || exit 1
    pids=("${pids[@]:1}")
  fi
done
for pid in "${pids[@]}"; do wait "$pid" || exit 1; done
"$cxx" -fsanitize=fuzzer,address,undefined "${objects[@]}" -lfmt -o "$work/fuzz_$target" || exit 1

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

if [ $# -gt 0 ]; then
  "$work/fuzz_$target" "$@"
  exit $?
fi

corpus="$work/corpus"
mkdir -p "$corpus" "$work/artifacts"
if [ "$target" = csv ]; then
  find "$root/tests/golden" "$root/models" -name '*.csv' -size -64k -exec cp {} "$corpus/" \; 2>/dev/null
  printf '\xef\xbb\xbftime,a\n0,1\n' >"$corpus/bom.csv"
  printf 'time;a\n0;1,5\n' >"$corpus/semicolon.csv"
  # The layouts campaigns record (fuzz_csv.cpp reads every input in each of them).
  printf 't;Ta;Ps;Time;yTi\n0;5.1;0.2;0;20.5\n0.25;5.0;0.3;0.25;20.4\n' >"$corpus/flexhouse.csv"
  printf 'time,heater_on,t1,t2\n1600356388.8088953,True,23.5,34.8\n1600356391.7,False,23.5,nan\n' \
    >"$corpus/unix_s.csv"
  printf 'x,time,lid\n1,1611326938000000000,on\n2,1611326941000000000,OFF\n3,1611326944000000001,yes\n' \
    >"$corpus/unix_ns.csv"
  printf 'T\twhen\n20\t2021-01-22T14:48:58.7Z\n21\t2021-01-22 14:58\n22\t2021-01-22T16:08:00+01:00\n' \
    >"$corpus/iso_tab.csv"
  printf 'a|t|b\n1|0|no\n2|1.5|Yes\n3|3|\n' >"$corpus/minutes_pipe.csv"
  printf 'unix ns\ntime,a\n0,1\n' >"$corpus/unit_line.csv"
else
  find "$root/tests/golden" -maxdepth 2 -name '*.tnet' -exec cp {} "$corpus/" \;
  find "$root/models" -name '*.tnet' -exec cp {} "$corpus/" \; 2>/dev/null
  # The forms of recorded campaigns, over the data files fuzz_parser.cpp puts beside the model.
  cat >"$corpus/campaign.tnet" <<'EOF'
param Aw = 0.2 [m^2] range -5 .. 5
const V = 12 [V]
boundary room T = table(data, "t1")
boundary out T = table("weather.csv", "To", time = "Time" [unix s], separator = ";") [degC]
node air C = 600 [J/K]
node wall C = 1e5
conductance g air room G = 0.5 ; conductance w wall out G = 2
heater lamp air P = V * 1.4 [A] * table(data, "heater_on", hold)
heater sun wall P = Aw * table("weather.csv", "I_sol", separator = ";", time = "Time" [unix s]) [W/m^2]
heater copy wall P = 0.5 * lamp.P + 2 [W] * sin(time / 600)
sensor probe air tau = 35 [s] offset = 0.4 gain = 1.01
sensor avg mean(air, wall) tau = 20
case run {
  duration = 9 [s]
  initial = data
  wall.T0 = 20 range 15 .. 30
  data "run.csv" time = "time" [unix s] { probe = mean(t2: 2, t3: 1) [degC]; room = t1 }
}
case lid {
  duration = 6 [s]
  initial = steady
  lamp.P = 2 * table(data, "heater_on", hold)
  data "lid_opening_experiment_jan_2021.csv" time = "time" [unix ns] {
    avg = mean(t2, t3)
  }
}
EOF
  cat >"$corpus/layouts.tnet" <<'EOF'
node a C = 10
boundary h T = table("flexhouse.csv", "Ta", time = "t" [h], separator = ";")
boundary i T = table("iso.csv", "T", time = "when" [iso]) [degC]
boundary m T = table("minutes.csv", "a", time = "minute" [min], hold) [K]
heater p a P = 1000 [W/kW] * table("flexhouse.csv", "Ps", time = "t" [h], separator = ";") [kW]
switched_conductance s a h G = 1 on = table("iso.csv", "on", time = "when" [iso], hold)
conductance c a i G = 1 ; conductance d a m G = 1
case flex {
  duration = 0.5 [h]
  data "flexhouse.csv" time = "t" [h] separator = ";" { a = yTi }
}
case tabbed { duration = 120 ; data "tab.csv" separator = "tab" { a = mean(a, "b") [K] } }
EOF
  # Deep nesting of the recursive forms: signals in signals, tables in expressions in tables.
  {
    printf 'heater h n P = '
    for _ in $(seq 30); do printf 'max(1, pwl(0: '; done
    printf 'table(data, "a", hold)'
    for _ in $(seq 30); do printf ', 1: 2))'; done
    printf '\nnode n C = 1\ncase c { duration = 20 ; data "data.csv" { n = mean(a, b, c) } }\n'
  } >"$corpus/nested_signals.tnet"
  {
    printf 'node n C = 1\nheater h0 n P = 1\n'
    for i in $(seq 1 200); do printf 'heater h%d n P = 2 * h%d.P\n' "$i" $((i - 1)); done
    printf 'case c { duration = 1 ; h0.P = table("data.csv", "a") }\n'
  } >"$corpus/reference_chain.tnet"
  {
    printf 'node n C = 1\nheater h[20001] n P = 1\n'
    printf 'for i in 1 .. 20000 { heater h[i] n P = 2 * h[i + 1].P }\n'
  } >"$corpus/reference_chain_loop.tnet"
  # Deep nesting of every recursive form of the grammar, at and just past its limits, within the
  # 4096 bytes an input may have: parentheses, calls, unary signs, powers, units, indices, loops
  # in the model and in a case, loop headers with many variables, submodel chains and cycles.
  python3 - "$corpus" <<'EOF'
import sys
out = sys.argv[1]
def seed(name, text):
    with open(f"{out}/deep_{name}.tnet", "w") as f:
        f.write(text[:4096])
for d in (63, 64, 65, 300):
    seed(f"parens{d}", "const x = " + "(" * d + "1" + ")" * d + "\nconst y = x\n")
    seed(f"calls{d}", "const x = " + "sqrt(" * d + "1" + ")" * d + "\n")
    seed(f"units{d}", "const x = 1 [W/" + "(" * d + "m" + ")" * d + "]\n")
    seed(f"index{d}", "node p[" + "(1 + " * d + "1" + ")" * d + "] C = 1\n")
    seed(f"signal{d}", "boundary b T = " + "step(0: " * d + "1" + ")" * d + "\n")
seed("minus", "const x = " + "-" * 3000 + "1\n")
seed("powers", "const x = 2" + "^2" * 1000 + "\n")
for d in (63, 64, 65):
    body = "".join("for a%d in 1 .. 2 {\n" % k for k in range(d))
    seed(f"loops{d}", "boundary b T = 20\n" + body + "node q[a0] C = 1\n" + "}\n" * d)
    seed(f"caseloops{d}", "node n C = 1\ncase c {\n  duration = 1\n" + body
         + "n.C = a0\n" + "}\n" * (d + 1))
seed("header", "boundary b T = 20\nfor " + ", ".join("v%d in 1 .. 1" % k for k in range(300))
     + " {\n  node q[v0 + v299] C = 1\n}\n")
seed("chain70", "boundary b T = 20\n" + "".join("submodel s%d(x) {\n  s%d i x\n}\n" % (k, k + 1)
                                                for k in range(70))
     + "submodel s70(x) {\n  node m C = 1\n}\ns0 top b\n")
seed("cycle", "boundary b T = 20\nsubmodel a(x) {\n  for i in 1 .. 2 { b u[i] x }\n}\n"
     "submodel b(x) {\n  c v x\n}\nsubmodel c(x) {\n  a w x\n}\nsubmodel s(x) {\n  s t x\n}\n")
seed("range", "for i in 1 .. 1000000000 { }\nnode p[1 .. 100000, 1 .. 100000] C = 1\n")
seed("twice", "node n C = 1\nheater h n P = 1\ncase c {\n  duration = 1\n  h.P = 2\n  h.P = 3\n"
     "  for i in 1 .. 2 { n.C = i }\n}\n")
EOF
fi
# A dictionary of the language's words helps the fuzzer past the keywords.
[ "$target" = csv ] && cat >"$work/tnet.dict" <<'EOF'
"time"
"Time"
"when"
"t"
","
";"
"|"
"\x09"
"nan"
"NA"
"1e308"
"-0"
"\""
"\x0d\x0a"
"\x0a"
"\xef\xbb\xbf"
"True"
"False"
"on"
"off"
"yes"
"NO"
"1600356388.8088953"
"1611326938000000000"
"2021-01-22T14:48:58.7Z"
"2021-01-22 14:48"
"+01:00"
"T"
"Z"
":"
"-"
"unix ns"
"unix s"
"iso"
"min"
EOF
[ "$target" = parser ] && cat >"$work/tnet.dict" <<'EOF'
"model"
"include"
"const"
"param"
"range"
"node"
"boundary"
"series"
"parallel"
"case"
"duration"
"initial"
"output"
"steady"
"data"
"for "
" in "
"for i in 1 .. 2, j in i .. 3 {"
"submodel "
"submodel s(x) {"
"s inner x"
"time"
"[i]"
"[i + 1, j]"
"[1 .. 10]"
".pcb"
", "
"[K]"
"step("
"pwl("
"table("
"table(data, "
"\"t1\""
", hold"
", time = \"Time\" [unix s]"
", separator = \";\""
"[unix ns]"
"[iso]"
"[h]"
") [W/m^2]"
" * table(data, \"heater_on\", hold)"
"lamp.P"
".T"
"sensor"
"sensor s air tau = 35"
"mean("
"offset = "
"gain = "
"initial = data"
" range 15 .. 30"
"w.T0 = 20"
"data \"run.csv\" time = \"time\" [unix s] {"
"{ air = mean(t2, t3) }"
"mean(t2: 2, t3: 1) [K]"
"switched_conductance"
"conductance"
"resistor"
"conduction"
"cylinder_conduction"
"contact"
"convection"
"radiation"
"heater"
"thermostat"
"sqrt("
"max("
"pow("
"pi"
"sigma"
" = "
" .. "
"[W/(m^2*K)]"
"[degC]"
"[mm]"
"[h]"
"\x0a"
"\\\x0a"
"{"
"}"
";"
"#"
"\""
EOF

echo "fuzz: running for $seconds s with corpus $corpus"
"$work/fuzz_$target" "$corpus" -dict="$work/tnet.dict" -max_total_time="$seconds" \
  -max_len=4096 -timeout=10 -rss_limit_mb=2048 -artifact_prefix="$work/artifacts/" \
  -print_final_stats=1 2>"$work/fuzz.log"
status=$?
tail -15 "$work/fuzz.log"
if [ "$status" -ne 0 ]; then
  echo "fuzz: FAILED (status $status)"
  grep -E "ERROR|SUMMARY|runtime error" "$work/fuzz.log" | head -20
  for crash in "$work"/artifacts/*; do
    [ -f "$crash" ] || continue
    echo "reproducer: $crash"
    od -c "$crash" | head -20
    [ -z "${FUZZ_BUILD_DIR:-}" ] && cp "$crash" "/tmp/$(basename "$crash")" &&
      echo "(copied to /tmp/$(basename "$crash"); replay with: $0 /tmp/$(basename "$crash"))"
  done
  exit 1
fi
echo "fuzz: no crash in $seconds s"
