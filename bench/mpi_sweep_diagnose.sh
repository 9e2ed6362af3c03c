#!/usr/bin/env bash
# MPI cost of `thermnet diagnose` and `thermnet sweep` (docs/cluster.md): wall time of one process
# and of 2 and 3 ranks (one thread each), the user CPU time of each rank, and a check that every
# output equals the single process's.
#   bench/mpi_sweep_diagnose.sh build/cli/thermnet
# diagnose: study A's nominal camera model against cases case03, case06 and case11 (the README
# workflow's quick run); sweep: case01 over a 40 x 50 grid of k7 and k12 (2,000 simulations).
# On a 2-core machine 3 ranks are oversubscribed: expect no gain past 2.
set -euo pipefail
T=$(realpath "$1")
M=$(realpath "$(dirname "$0")/../models/aerial_camera/camera.tnet")
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
W=$(mktemp -d); trap 'rm -rf "$W"' EXIT
run() { # label ranks args...: prints label, ranks, wall time and each rank's user CPU time
  local label=$1 n=$2; shift 2
  local launch=() t0 t1
  [ "$n" = 1 ] || launch=(mpirun -n "$n" --oversubscribe)
  t0=$(date +%s.%N)
  (cd "$W" && "${launch[@]}" /usr/bin/time -f "cpu %U" "$T" "$@" >"$label$n.out" 2>"$label$n.err")
  t1=$(date +%s.%N)
  echo "$label $n $(echo "$t1 - $t0" | bc -l) $(awk '/^cpu/ {print $2}' "$W/$label$n.err" | paste -sd/)"
}
for n in 1 2 3; do
  run diagnose "$n" diagnose "$M" --case case03 --case case06 --case case11 --top 3 --threads 1 \
    --json "diagnose$n.json"
  sed 's/"wall_s": .*/"wall_s": -/' "$W/diagnose$n.json" >"$W/diagnose$n.cmp"
  run sweep "$n" sweep "$M" --case case01 --param k7=2..15:40 --param k12=0.03..0.2:50 \
    --threads 1 -o "sweep$n.csv"
done | awk '
  { if ($2 == 1) base[$1] = $3
    printf "%-8s %d rank%s  %7.2f s  speed-up %.2f  user CPU per rank %s s\n", $1, $2,
           ($2 == 1 ? " " : "s"), $3, base[$1] / $3, $4 }'
for n in 2 3; do
  cmp -s "$W/diagnose1.out" "$W/diagnose$n.out" || { echo "diagnose: text of $n ranks differs"; exit 1; }
  cmp -s "$W/diagnose1.cmp" "$W/diagnose$n.cmp" || { echo "diagnose: JSON of $n ranks differs"; exit 1; }
  cmp -s "$W/sweep1.csv" "$W/sweep$n.csv" || { echo "sweep: table of $n ranks differs"; exit 1; }
done
echo "outputs on 2 and 3 ranks identical to 1 process (diagnose JSON without wall_s)"
