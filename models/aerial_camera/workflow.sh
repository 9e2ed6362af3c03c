#!/bin/sh
# Study A workflow (docs/aerial_camera.md): nominal model vs SYNTHETIC data (make_data.py: an
# independent SciPy camera that differs from the model as hardware would), diagnosis, the model
# extension written by `thermnet diagnose --write`, Monte Carlo calibration of that extended model at
# 3000/6000/12000 samples plus lhs, ga, lm, plots, summary (also written to $OUT/summary.txt).
# Usage: models/aerial_camera/workflow.sh [PATH/TO/thermnet]
#   QUICK=1   fewer samples (300/600/1200, ga 200) and diagnosis on 3 of the 11 cases (tests)
#   OUT=DIR   where reports and plots go (default /tmp/aerial_camera_out); IMG=DIR copies plots
#   THREADS=N worker threads (default: all cores)
# Exits non-zero when a step fails or when diagnose names no window-barrel <-> lens-1 link among
# its findings, their rival candidates and its alternatives.
set -e
HERE=$(cd "$(dirname "$0")" && pwd)
T=${1:-${THERMNET:-thermnet}}
OUT=${OUT:-/tmp/aerial_camera_out}
THREADS=${THREADS:-$(nproc)}
PY=/usr/bin/python3
if [ "${QUICK:-0}" = 1 ]; then
  S1=300; S2=600; S3=1200; GA=200; DIAG_CASES="--case case03 --case case06 --case case11"
else
  S1=3000; S2=6000; S3=12000; GA=1000; DIAG_CASES=""
fi
start=$(date +%s)
LOG="$OUT/workflow.log"
# quiet: runs a command with its output in $LOG; on failure shows the end of $LOG and stops
quiet() {
  "$@" >>"$LOG" 2>&1 || { echo "workflow: failed: $*" >&2; tail -n 20 "$LOG" >&2; exit 1; }
}
# diagnose --write puts the extension next to the model it extends (its includes are relative), so
# the workflow works on a scratch copy of the model and its data: the repository stays untouched.
M="$OUT/model"
rm -rf "$M"
mkdir -p "$M"
: >"$LOG"
cp "$HERE"/*.tnet "$M"/
cp -R "$HERE/data" "$M/data"

echo "== 0. lint"
"$T" lint "$HERE/camera.tnet" "$HERE/extended.tnet" --werror

echo "== 1+2. nominal model against the data, and diagnosis"
# Jacobians from CVODES sensitivities: on this camera (24 nodes, 11 cases, joint refits of 11 params)
# the same findings as with forward differences in a tenth less time (docs/aerial_camera.md).
# shellcheck disable=SC2086 # DIAG_CASES is a list of options
"$T" diagnose "$M/camera.tnet" $DIAG_CASES --threads "$THREADS" --top 3 --jacobian sensitivities \
  --json "$OUT/diag_nominal.json" --html "$OUT/aerial_diagnose.html" \
  --write "$M/extended_diagnosed.tnet" --plot "$OUT/aerial_diagnose.svg"
quiet "$T" calibrate "$M/camera.tnet" --method lm --samples 1 --threads "$THREADS" --json "$OUT/nominal.json"
$PY - "$OUT/diag_nominal.json" <<'PYEOF'
import json, sys
d = json.load(open(sys.argv[1]))
if not d["findings"]:
    sys.exit("workflow: diagnose reported no finding, so there is no extension to calibrate")
# Where diagnose names the study's structure correction: a finding, a rival candidate of one (fits
# as well), or an alternative (significant alone, explained by a finding above).
def link(c):
    return "wbarrel" in c["nodes"] and any(n.startswith("lens1") for n in c["nodes"])
named = [f"finding {i + 1}" for i, f in enumerate(d["findings"]) if link(f)]
named += [f"candidate {k} of finding {i + 1}" for i, f in enumerate(d["findings"])
          for k, c in enumerate(f.get("candidates", [])) if k > 0 and link(c)]
named += [f"alternative {i + 1}" for i, f in enumerate(d["alternatives"]) if link(f)]
if not named:
    sys.exit("workflow: diagnose names no window-barrel <-> lens-1 link (the study's structure "
             "correction) among its findings, their candidates and its alternatives")
print("workflow: the window-barrel <-> lens-1 link is named as " + ", ".join(named))
PYEOF

echo "== 3. extended model: the nominal model plus diagnose's extension ($M/extended_diagnosed.tnet)"
sed -n '/^# thermnet diagnose:/,$p' "$M/extended_diagnosed.tnet" | grep -v '^# \(param\|fitted\)'
"$T" lint "$M/extended_diagnosed.tnet" --werror
quiet "$T" calibrate "$M/extended_diagnosed.tnet" --method lm --samples 1 --threads "$THREADS" --json "$OUT/extended.json"

echo "== 4. calibration of the extended model"
E="$M/extended_diagnosed.tnet"
for s in $S1 $S2 $S3; do
  quiet "$T" calibrate "$E" --method mc --samples "$s" --seed 1 --threads "$THREADS" --json "$OUT/mc_$s.json"
done
quiet "$T" calibrate "$E" --method lhs --samples "$S1" --seed 1 --threads "$THREADS" --json "$OUT/lhs_$S1.json"
quiet "$T" calibrate "$E" --method ga --samples "$GA" --seed 1 --threads "$THREADS" --json "$OUT/ga.json"
quiet "$T" calibrate "$E" --method lm --threads "$THREADS" --json "$OUT/lm.json"
quiet "$T" calibrate "$M/camera.tnet" --method lm --threads "$THREADS" --json "$OUT/lm_nominal.json"
# The study's structure correction written by hand in its own form (extended.tnet: convection with
# h_wl = 15 W/(m^2 K) plus radiation, link.tnet), for comparison with diagnose's conductance.
quiet "$T" calibrate "$M/extended.tnet" --method lm --threads "$THREADS" --json "$OUT/lm_handwritten.json"

echo "== 5. plots (case03: measured, nominal, extended + lm values)"
# `calibrate -o` cannot yet rewrite params declared in included files, so the calibrated model is
# written here: diagnose's extended model with params_nominal.tnet replaced by the lm values.
$PY - "$OUT/lm.json" "$M" <<'PYEOF'
import json, re, sys
r, m = json.load(open(sys.argv[1])), sys.argv[2]
units = r["param_units"]
text = open(f"{m}/params_nominal.tnet").read()
for k, v in r["params"].items():
    # the declared units of the ranged params are all coherent SI units: the SI value is written as is
    assert units[k] in ("W/(m*K)", "W/K", "W/(m^2*K)", "K/W", "bare number"), units[k]
    text, n = re.subn(rf"^(param {k}\s*=\s*)[-+0-9.eE]+", rf"\g<1>{v!r}", text, flags=re.M)
    assert n == 1, k
open(f"{m}/params_calibrated.tnet", "w").write("# params_nominal.tnet with the lm values (workflow.sh)\n" + text)
ext = open(f"{m}/extended_diagnosed.tnet").read().replace('include "params_nominal.tnet"', 'include "params_calibrated.tnet"')
open(f"{m}/extended_calibrated.tnet", "w").write(ext)
PYEOF
sed -n 's/^case \(case[0-9]*\) .*/\1/p' "$HERE/cases.tnet" | while read -r c; do
  quiet "$T" simulate "$M/camera.tnet" --case "$c" -o "$OUT/nominal_$c.csv"
done
quiet "$T" simulate "$M/extended_calibrated.tnet" --case case03 -o "$OUT/after.csv"
TOFF=$(sed -n 's/^case case03 .*t_off = \([0-9.]*\) \[s\].*/\1/p' "$HERE/cases.tnet")
$PY "$HERE/plot_case.py" "$M/data/case03.csv" "$OUT/nominal_case03.csv" "$OUT/after.csv" "$OUT/aerial_case03.svg" \
  "case03: measured (SYNTHETIC) vs nominal and calibrated extended model" "$TOFF"
if [ -n "$IMG" ]; then cp "$OUT"/aerial_diagnose.svg "$OUT"/aerial_case03.svg "$IMG"/; fi

echo "== summary (also in $OUT/summary.txt)"
$PY - "$OUT" "$M" "$HERE" $S1 $S2 $S3 >"$OUT/summary.txt" <<'PYEOF'
import ast, json, sys
import numpy as np
out, m, here, s1, s2, s3 = sys.argv[1], sys.argv[2], sys.argv[3], *sys.argv[4:]
# The synthetic camera's params (what calibration should find), read from make_data.py's text (the
# quick start runs without SciPy, which importing it would need).
TRUE_PARAMS = next(ast.literal_eval(n.value) for n in ast.parse(open(f"{here}/make_data.py").read()).body
                   if isinstance(n, ast.Assign) and getattr(n.targets[0], "id", "") == "TRUE_PARAMS")
d = json.load(open(f"{out}/diag_nominal.json"))
rows = []
runs = {}
for name, fn in [("nominal (declared values)", "nominal.json"), ("nominal, lm", "lm_nominal.json"),
                 ("extended (declared values)", "extended.json"), (f"mc {s1}", f"mc_{s1}.json"),
                 (f"mc {s2}", f"mc_{s2}.json"), (f"mc {s3}", f"mc_{s3}.json"), (f"lhs {s1}", f"lhs_{s1}.json"),
                 ("ga", "ga.json"), ("lm", "lm.json"), ("hand-written link, lm", "lm_handwritten.json")]:
    r = runs[name] = json.load(open(f"{out}/{fn}"))
    declared = "declared" in name
    rows.append((name, "-" if declared else r["evaluations"], "-" if declared else r["accepted"],
                 r["rmse"], r["r2"], "-" if declared else f'{r["wall_s"]:.1f}'))
print(f'{"model / method":28s} {"evals":>6s} {"kept":>6s} {"RMSE K":>7s} {"R2":>7s} {"wall s":>7s}')
for n, ev, ac, r, r2, w in rows:
    print(f"{n:28s} {ev!s:>6s} {ac!s:>6s} {r:7.3f} {r2:7.4f} {w:>7s}")
print(f'diagnose ({len(d["cases"])} cases): noise about {d["noise_floor"]:.3f} K, baseline RMSE {d["baseline"]["rmse"]:.3f} K')
for i, f in enumerate(d["findings"]):
    v = ", ".join(f"{k} = {x:.4g}" for k, x in f["values"].items() if not k.startswith("k"))
    mech = f' {f["mechanism"]}' if f.get("mechanism") else ""
    print(f'  finding {i + 1}: {f["kind"]}{mech} {f["nodes"]} ({v}): RMSE {f["rmse_before"]:.3f} -> '
          f'{f["rmse_after"]:.3f} K, held-out {f["validation_rmse_before"]:.3f} -> {f["validation_rmse_after"]:.3f} K')
for f in d["alternatives"]:
    print(f'  alternative: {f["kind"]} {f["nodes"]}: RMSE {f["rmse_after"]:.3f} K')
# The params: what the lm fits give against the synthetic camera's own values (make_data.py).
ranged = runs["lm"]["params"]
print(f'{"param":6s} {"true":>8s} {"lm, diagnosed link":>19s} {"lm, hand-written":>17s} {"lm, nominal":>12s}')
for k in ranged:
    print(f'{k:6s} {TRUE_PARAMS[k]:8.4g} {ranged[k]:19.4g} {runs["hand-written link, lm"]["params"][k]:17.4g} '
          f'{runs["nominal, lm"]["params"][k]:12.4g}')
w = d["baseline"]["nodes"]["wbarrel"]
print(f'window barrel, nominal model: RMSE {w["rmse"]:.2f} K, trend disagreement {w["trend_mismatch_s"]:.0f} s in total')
# The study's symptom per case: after the heater stops, how long the measured window barrel keeps
# rising (peak of the data smoothed over 5 samples) and how long the nominal model's does.
print(f'{"case":6s} {"P W":>4s} {"stop s":>6s} {"trend disagreement s":>21s} {"peak after stop: measured":>26s} {"nominal":>8s}')
for line in open(f"{m}/cases.tnet"):
    if not line.startswith("case "):
        continue
    c = line.split()[1]
    p, t_off = (float(line.split(k + " = ")[1].split()[0]) for k in ("P_heat", "t_off"))
    mea = np.genfromtxt(f"{m}/data/{c}.csv", delimiter=",", names=True)
    nom = np.genfromtxt(f"{out}/nominal_{c}.csv", delimiter=",", names=True)
    smooth = np.convolve(mea["wbarrel"], np.ones(5) / 5, mode="same")
    def peak_after(t, y):
        k = (t >= t_off) & (t <= t[-1] - 240)
        return t[k][np.argmax(y[k])] - t_off
    diagnosed = d["baseline"]["cases"].get(c)  # QUICK=1 diagnoses 3 cases only
    tm = f'{diagnosed["nodes"]["wbarrel"]["trend_mismatch_s"]:.0f}' if diagnosed else "-"
    print(f'{c:6s} {p:4g} {t_off:6g} {tm:>21s} {peak_after(mea["time"], smooth):24.0f} s {peak_after(nom["time"], nom["wbarrel"]):6.0f} s')
mea = np.genfromtxt(f"{m}/data/case03.csv", delimiter=",", names=True)
for label, fn in (("nominal", "nominal_case03.csv"), ("calibrated extended", "after.csv")):
    sim = np.genfromtxt(f"{out}/{fn}", delimiter=",", names=True)
    e = np.interp(mea["time"], sim["time"], sim["wbarrel"]) - mea["wbarrel"]
    print(f"case03 window barrel, {label}: RMSE {np.sqrt(np.mean(e ** 2)):.2f} K")
PYEOF
cat "$OUT/summary.txt"
echo "workflow wall time: $(( $(date +%s) - start )) s"
