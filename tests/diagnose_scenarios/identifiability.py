#!/usr/bin/python3
"""How much of each scenario's hidden effect recalibrating the ranged params alone can explain,
computed with the generator's own SciPy simulator (not thermnet).

For every scenario it fits the nominal network's ranged params (log scale, inside their ranges,
scipy least_squares from the nominal values) to the NOISE-FREE readings of the truth and reports
the residual that remains: its RMS and peak over all measured points. A residual far below the
sensor noise means the data cannot tell the structural effect from a parameter error (an honest
diagnosis then reports `parameter`); the runner shows this number next to each scenario.

It takes minutes per large scenario, so it is run by hand when the table or the generator
changes, and its results are kept in identifiability.csv with a checksum of the scenario's data;
the runner ignores a row whose checksum no longer matches.

Usage: identifiability.py [ID ...]   (default: every scenario; rewrites identifiability.csv)
"""
from __future__ import annotations

import csv
import os
import sys

import numpy as np
from scipy.optimize import least_squares

import generate
import truth as tr

FILE = os.path.join(generate.HERE, "identifiability.csv")
FIELDS = ["id", "checksum", "param_only_rmse", "param_only_peak", "evaluations"]


def param_only_fit(s: generate.Scenario) -> tuple[float, float, int]:
    """(RMS, peak, simulations) of the noise-free truth minus the best param-only nominal model."""
    net, names = s.net, [p.name for p in s.net.params]
    idx = [[n.name for n in net.nodes].index(a) for a in s.measured]
    lo = np.log([p.lo for p in net.params])
    hi = np.log([p.hi for p in net.params])
    x0 = np.clip(np.log([p.nominal for p in net.params]), lo + 1e-9, hi - 1e-9)
    calls = [0]

    def residual(x):
        calls[0] += 1
        p = dict(zip(names, np.exp(x)))
        out = [tr.simulate(net, p, c)[1][:, idx] - R for c, R in zip(net.cases, s.clean)]
        return np.concatenate([r.ravel() for r in out])

    fit = least_squares(residual, x0, bounds=(lo, hi), diff_step=1e-4, xtol=1e-6, ftol=1e-8, max_nfev=40)
    r = fit.fun
    return float(np.sqrt(np.mean(r**2))), float(np.abs(r).max()), calls[0]


def load() -> dict[str, dict]:
    if not os.path.exists(FILE):
        return {}
    with open(FILE) as f:
        return {r["id"]: r for r in csv.DictReader(line for line in f if not line.startswith("#"))}


def main() -> int:
    rows = generate.load_table()
    wanted = set(sys.argv[1:]) or {r["id"] for r in rows}
    known = load()
    for row in rows:
        if row["id"] not in wanted:
            continue
        s = generate.build(row)
        rms, peak, n = param_only_fit(s) if s.effects else (0.0, 0.0, 0)
        known[row["id"]] = {"id": row["id"], "checksum": generate.data_checksum(s), "param_only_rmse": f"{rms:.4f}",
                            "param_only_peak": f"{peak:.4f}", "evaluations": n}
        print(f"{row['id']}: param-only residual RMS {rms:.3f} K, peak {peak:.3f} K ({n} simulations)", flush=True)
    with open(FILE, "w") as f:
        f.write("# written by identifiability.py: what recalibrating the ranged params alone leaves of each\n"
                "# scenario's noise-free truth (K); checksum identifies the data it was computed for\n")
        w = csv.DictWriter(f, FIELDS)
        w.writeheader()
        for row in rows:
            if row["id"] in known:
                w.writerow({k: known[row["id"]][k] for k in FIELDS})
    return 0


if __name__ == "__main__":
    sys.exit(main())
