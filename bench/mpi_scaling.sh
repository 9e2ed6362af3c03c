#!/usr/bin/env bash
# MPI strong scaling (docs/cluster.md): a 12,000-sample Monte Carlo calibration of the extended aerial
# camera model of study A (all 11 cases) and a 400-sample uncertainty run, on 1, 2 and 4 ranks with one thread
# each; prints wall times, speed-up and efficiency, and checks every result against 1 rank.
#   bench/mpi_scaling.sh build/cli/thermnet [MC_SAMPLES] [UQ_SAMPLES]
# On a 2-core machine 4 ranks are oversubscribed: expect no gain past 2.
set -euo pipefail
T=$(realpath "$1"); MC=${2:-12000}; UQ=${3:-400}
M=$(realpath "$(dirname "$0")/../models/aerial_camera/extended.tnet")
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
W=$(mktemp -d); trap 'rm -rf "$W"' EXIT
run() { # ranks label args...
  local n=$1 label=$2; shift 2
  local t0 t1; t0=$(date +%s.%N)
  if [ "$n" = 1 ]; then "$T" "$@" >/dev/null 2>&1; else mpirun -n "$n" --oversubscribe "$T" "$@" >/dev/null 2>&1; fi
  t1=$(date +%s.%N); echo "$label $n $(echo "$t1 - $t0" | bc -l)"
}
for n in 1 2 4; do
  run "$n" mc calibrate "$M" --method mc --samples "$MC" --seed 1 --threads 1 --json "$W/mc$n.json"
  grep -v wall_s "$W/mc$n.json" > "$W/mc$n.cmp"
  run "$n" uq simulate "$M" --case case01 --samples "$UQ" --threads 1 -o "$W/uq$n.csv"
done | awk -v mc="$MC" -v uq="$UQ" '
  { t[$1,$2] = $3; if ($2 == 1) base[$1] = $3
    printf "%-3s %6d samples  %d rank%s  %7.2f s  speed-up %.2f  efficiency %3.0f %%\n", $1,
           ($1 == "mc" ? mc : uq), $2, ($2 == 1 ? " " : "s"), $3, base[$1] / $3,
           100 * base[$1] / $3 / $2 }'
for n in 2 4; do
  cmp -s "$W/mc1.cmp" "$W/mc$n.cmp" || { echo "mc: $n ranks differ from 1"; exit 1; }
  cmp -s "$W/uq1.csv" "$W/uq$n.csv" || { echo "uq: $n ranks differ from 1"; exit 1; }
done
echo "results on 2 and 4 ranks identical to 1 rank (JSON without wall_s; CSV byte for byte)"
