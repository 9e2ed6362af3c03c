#!/usr/bin/env bash
# Compile cost of a build, unit by unit: configures a fresh build folder without ccache, builds the
# given targets with every compiler and linker call timed (CPU user + system and wall seconds), and
# prints the total and the heaviest units. CPU seconds hardly depend on what else the machine runs
# (the wall time does); a 2-core machine's build takes about CPU / 2 when both cores are busy.
#   bench/compile_times.sh BUILD_DIR [TARGET...] [-- CMAKE_OPTION...]   (default target: thermnet)
#   e.g. bench/compile_times.sh /tmp/ct thermnet -- -DTHERMNET_UNITY_BUILD=ON
set -euo pipefail
SRC=$(cd "$(dirname "$0")/.." && pwd)
DIR=$1; shift
targets=(); opts=()
while [ $# -gt 0 ]; do
  if [ "$1" = -- ]; then shift; opts=("$@"); break; fi
  targets+=("$1"); shift
done
[ ${#targets[@]} -gt 0 ] || targets=(thermnet)
rm -rf "$DIR"; mkdir -p "$DIR"
LOG="$DIR/compile_times.log"
# The launcher: runs the compiler (or linker) under /usr/bin/time, one line per call.
cat >"$DIR/timed" <<LAUNCHER
#!/bin/sh
out=\$(for a in "\$@"; do case "\$prev" in -o) echo "\$a";; esac; prev=\$a; done | tail -n 1)
exec /usr/bin/time -a -o "$LOG" -f "%U %S %e \$out" "\$@"
LAUNCHER
chmod +x "$DIR/timed"
cmake -S "$SRC" -B "$DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER_LAUNCHER="$DIR/timed" \
  -DCMAKE_CXX_LINKER_LAUNCHER="$DIR/timed" "${opts[@]}" >/dev/null
: >"$LOG"
start=$(date +%s%N)
cmake --build "$DIR" --parallel 2 --target "${targets[@]}" >"$DIR/build.log" 2>&1 ||
  { echo "compile_times: the build failed, see $DIR/build.log" >&2; exit 1; }
wall=$(( ($(date +%s%N) - start) / 1000000000 ))
awk -v wall="$wall" -v load="$(cut -d' ' -f1-3 /proc/loadavg)" '
  { cpu = $1 + $2; total += cpu; n++; line[n] = sprintf("%7.1f %7.1f  %s", cpu, $3, $4); key[n] = cpu }
  END {
    printf "%d calls, CPU %.0f s (user+sys), wall %.0f s on 2 jobs; load average at the end %s\n", n, total, wall, load
    printf "    CPU    wall  unit (heaviest 15)\n"
    for (k = 1; k <= 15 && k <= n; k++) { best = 0; for (i = 1; i <= n; i++) if (!(i in done) && (best == 0 || key[i] > key[best])) best = i; done[best] = 1; print line[best] }
  }' "$LOG"
