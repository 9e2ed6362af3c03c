#!/usr/bin/env bash
# Builds a libFuzzer target with clang++-14 (ASan + UBSan) and runs it for a bounded time.
#
#   FUZZ_TARGET=csv run.sh        # the target: parser (default, fuzz_parser.cpp) or csv
#   FUZZ_SECONDS=60 run.sh        # default 60 s
#   FUZZ_BUILD_DIR=DIR run.sh     # keep objects and the corpus in DIR (default: a temp folder)
#   run.sh CRASH_FILE...          # replay reproducers instead of fuzzing
#
# The corpus is seeded from tests/golden and models/ (*.tnet, or *.csv up to 64 KB for csv).
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
    "$root"/lang/path_policy.cpp "$here"/fuzz_csv.cpp)
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
  $launcher "$cxx" "${flags[@]}" -c "$src" -o "$obj" &
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
else
  find "$root/tests/golden" -maxdepth 2 -name '*.tnet' -exec cp {} "$corpus/" \;
  find "$root/models" -name '*.tnet' -exec cp {} "$corpus/" \; 2>/dev/null
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
","
";"
"nan"
"NA"
"1e308"
"-0"
"\""
"\x0d\x0a"
"\x0a"
"\xef\xbb\xbf"
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
