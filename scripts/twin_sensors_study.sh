#!/usr/bin/env bash
# Hidden-node RMSE of the digital twin (models/digital_twin) as sensors are removed: runs
# `thermnet estimate` (EKF, and the RTS smoother) on the SYNTHETIC twin_data.csv and prints a
# Markdown table (docs/inverse.md). Usage: twin_sensors_study.sh PATH/TO/thermnet
set -eu
TN=${1:-thermnet}
M=$(cd "$(dirname "$0")/../models/digital_twin" && pwd)
echo "| measured nodes | n | EKF l1_centre K | EKF l2_centre K | RTS l1_centre K | RTS l2_centre K | ms/step |"
echo "|---|---|---|---|---|---|---|"
for set in window,l1_edge,l2_edge,barrel,inner,outer l1_edge,l2_edge,barrel,inner,outer \
           l1_edge,l2_edge,barrel,outer l1_edge,l2_edge,barrel l1_edge,barrel barrel outer; do
  f=$("$TN" estimate "$M/twin.tnet" "$M/twin_data.csv" --case known --measured "$set" -o /dev/null 2>&1)
  s=$("$TN" estimate "$M/twin.tnet" "$M/twin_data.csv" --case known --measured "$set" --smooth -o /dev/null 2>&1)
  get() { echo "$1" | awk -v k="$2" '$3 == k { printf "%.2f", $5 * ($6 == "s" ? 1000 : 1) }'; }
  n=$(echo "$set" | tr ',' '\n' | wc -l)
  echo "| $set | $n | $(get "$f" rmse_l1_centre) | $(get "$f" rmse_l2_centre) | $(get "$s" rmse_l1_centre) | $(get "$s" rmse_l2_centre) | $(get "$f" step_time_mean) |"
done
f=$("$TN" estimate "$M/twin.tnet" "$M/twin_data.csv" --case twin --estimate-input barrel \
     --measured window,l1_edge,l2_edge,barrel,inner,outer -o /dev/null 2>&1)
echo
echo "Unknown heater (case twin, --estimate-input barrel, six sensors): $(echo "$f" | grep -E 'rmse_l|input_final' | awk '{printf "%s = %.2f %s; ", $3, $5, $6}')"
