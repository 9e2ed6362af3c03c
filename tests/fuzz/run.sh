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
"submodel "
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
