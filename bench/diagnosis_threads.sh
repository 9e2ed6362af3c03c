#!/bin/bash
# The diagnosis's thread scaling (issue 30): `thermnet diagnose --stats` of generated scenarios at
# several thread counts, one run after the other, with each run's wall, user and system seconds
# (bash's time) and its --stats summary in OUT/log.txt; the JSON reports are kept in OUT to check
# that they are identical whatever the thread count.
#
# Usage: bench/diagnosis_threads.sh SCENARIOS OUT ID:THREADS...
#   SCENARIOS  a folder of scenario folders named by id, made here by
#              tests/diagnose_scenarios/generate.py ID SCENARIOS/ID [--table bench/diagnosis.csv]
#              (or bench/diagnosis.py --keep SCENARIOS)
#   ID:THREADS e.g. S19:16 B72:16 B72:8 B72:2 S19:2
# THERMNET: the command that runs thermnet (default: build/cli/thermnet); on a machine without
# thermnet's packages, a bundle of bench/bundle_binary.sh:
#   THERMNET="B/lib/ld-linux-x86-64.so.2 --library-path B/lib B/bin/thermnet"
set -u
[ $# -ge 3 ] || { echo "usage: $0 SCENARIOS OUT ID:THREADS..." >&2; exit 2; }
scen=$(cd "$1" && pwd) out=$2
shift 2
mkdir -p "$out"
out=$(cd "$out" && pwd)
read -r -a tn <<<"${THERMNET:-$(dirname "$0")/../build/cli/thermnet}"
log=$out/log.txt
{ nproc; grep -m1 'model name' /proc/cpuinfo; } >>"$log"
TIMEFORMAT='%R wall %U user %S sys'
status=0
for run in "$@"; do
  id=${run%%:*} threads=${run##*:}
  echo "== $id, $threads threads" >>"$log"
  { time (cd "$scen/$id" && "${tn[@]}" diagnose model.tnet --stats --threads "$threads" \
    --json "$out/${id}_t$threads.json" >"$out/${id}_t$threads.txt" 2>"$out/${id}_t$threads.err"); } 2>>"$log" ||
    status=1
  head -7 "$out/${id}_t$threads.err" >>"$log"
done
cat "$log"
exit $status
