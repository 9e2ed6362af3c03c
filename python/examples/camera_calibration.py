#!/usr/bin/env python3
"""Notebook-style example (docs/python.md): calibrate the bundled aerial camera from Python and
plot measured against simulated lens temperatures with matplotlib.

    /usr/bin/python3 python/examples/camera_calibration.py [OUT_DIR]

Each `# %%` cell can be pasted into a Jupyter notebook as it is.
"""

# %% Load the model: 24 nodes, 11 measured cases, 9 ranged params.
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files, no window (drop this line in a notebook)
import matplotlib.pyplot as plt
import pandas as pd

import thermnet

here = os.path.dirname(os.path.abspath(__file__))
model_path = os.path.join(here, "..", "..", "models", "aerial_camera", "camera.tnet")
out_dir = sys.argv[1] if len(sys.argv) > 1 else "out/python_example"
os.makedirs(out_dir, exist_ok=True)

m = thermnet.Model.load(model_path)
print(m, "ranged params:", [n for n, p in m.params.items() if p["lo"] is not None])

# %% Calibrate with Levenberg-Marquardt on three cases: the report is `calibrate --json`.
report = m.calibrate(method="lm", cases=["case01", "case04", "case07"])
print(f"RMSE {report['rmse']:.3f} K, R² {report['r2']:.4f}, {report['evaluations']} evaluations")
for name, value in report["params"].items():
    print(f"  {name} = {value:.4g} {report['param_units'].get(name, '')}")

# %% Simulate a held-out case with the nominal and the calibrated params.
case, nodes = "case10", ["lens1_c", "lens4_c", "barrel1"]
nominal = m.simulate(case=case, nodes=nodes).to_pandas()
fitted = m.simulate(case=case, nodes=nodes, params=report["params"]).to_pandas()
measured = pd.read_csv(os.path.join(os.path.dirname(model_path), "data", f"{case}.csv"),
                       index_col="time")

# %% Plot: measured markers, nominal dashed, calibrated solid.
fig, ax = plt.subplots(figsize=(8, 4.5))
for i, node in enumerate(nodes):
    color = f"C{i}"
    ax.plot(measured.index / 60, measured[node], "o", ms=2, color=color, label=f"{node} measured")
    ax.plot(nominal.index / 60, nominal[node], "--", color=color, label=f"{node} nominal")
    ax.plot(fitted.index / 60, fitted[node], "-", color=color, label=f"{node} calibrated")
ax.set_xlabel("time [min]")
ax.set_ylabel("temperature [°C]")
ax.set_title(f"aerial camera, {case} (not used by the fit)")
ax.legend(fontsize=7, ncol=3)
fig.tight_layout()
png = os.path.join(out_dir, "camera_calibration.png")
fig.savefig(png, dpi=110)

# %% How much better on the held-out case: RMSE at the measured times.
def rmse(sim):
    at = sim.reindex(measured.index, method="nearest")
    return float(((at[nodes] - measured[nodes]) ** 2).to_numpy().mean() ** 0.5)


print(f"{case}: RMSE nominal {rmse(nominal):.3f} K -> calibrated {rmse(fitted):.3f} K; plot {png}")
