#!/usr/bin/env bash
# Real measured data read as published and calibrated by thermnet, against independent SciPy fits
# of the same structures (scipy_fits.py): the INTO-CPS incubator's three experiments with its
# published 2-parameter model, and the Armadillo Box sequence with the published 2R2C model.
#   run.sh THERMNET
set -euo pipefail
bin=$1
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
models=$here/../../models
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
failed=0

# calibrate MODEL SCIPY_FIT: thermnet's Levenberg-Marquardt fit must reach the RMSE SciPy's
# least_squares reaches on the same structure (1 % slack: two solvers' tolerances).
calibrate() {
  local model=$1 fit=$2 name
  name=$(basename "$model" .tnet)
  "$bin" lint --werror "$model" >/dev/null
  "$bin" calibrate "$model" --method lm --json "$out/$name.json" >"$out/$name.txt"
  /usr/bin/python3 "$here/scipy_fits.py" "$fit" >"$out/$name.scipy"
  /usr/bin/python3 - "$out/$name.json" "$out/$name.scipy" "$name" <<'PY' || failed=1
import json, sys
mine = json.load(open(sys.argv[1]))
ref = dict(line.split() for line in open(sys.argv[2]))
rmse, scipy = mine["rmse"], float(ref["rmse"])
print(f"{sys.argv[3]}: thermnet calibrate lm RMSE {rmse:.4f} K, SciPy least_squares {scipy:.4f} K")
for k, v in mine["params"].items():
    print(f"  {k}: thermnet {v:.5g}, SciPy {float(ref.get(k, 'nan')):.5g}")
if not rmse <= 1.01 * scipy:
    sys.exit(f"FAIL: {sys.argv[3]}: thermnet's fit {rmse:.4f} K is worse than SciPy's {scipy:.4f} K")
PY
}

calibrate "$models/incubator/incubator.tnet" incubator2
calibrate "$models/armadillo/house_2r2c.tnet" house2r2c
exit $failed
