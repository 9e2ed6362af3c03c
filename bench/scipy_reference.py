#!/usr/bin/python3
"""SciPy BDF solution of a plate network written by bench/plate.py (plate_*.json).

dT/dt = (1/C) [ -L T + Gc (T_air - T) - sigma GR (T^4 - T_sink^4) + P(t) ]   (T in kelvin)
solved with solve_ivp(method="BDF") and the analytic sparse Jacobian (jac_sparsity given too);
the integration is restarted at every heater step time (the same breakpoints thermnet uses).

Usage: scipy_reference.py NET.json [--rtol R --atol A | --reference] [--out FINAL.txt]
Prints `probe NAME T_degC` lines and `wall_s W` (the solve only: JSON loading and matrix
assembly excluded). --reference = rtol 1e-9, atol 1e-9. --out writes every node's final degC.
"""
import argparse
import json
import sys
import time

import numpy as np
import scipy.sparse as sp
from scipy.integrate import solve_ivp

K = 273.15


def assemble(d):
    n = len(d["C"])
    C = np.asarray(d["C"], float)
    e = np.asarray(d["edges"], int).reshape(-1, 2)
    G = np.asarray(d["G"], float)
    a, b = e[:, 0], e[:, 1]
    diag = np.zeros(n)
    np.add.at(diag, a, G)
    np.add.at(diag, b, G)
    gc = np.zeros(n)
    np.add.at(gc, np.asarray(d["conv_nodes"], int), np.asarray(d["conv_G"], float))
    diag += gc
    L = sp.coo_matrix((np.concatenate([-G, -G, diag]),
                       (np.concatenate([a, b, np.arange(n)]), np.concatenate([b, a, np.arange(n)]))),
                      shape=(n, n)).tocsr()
    A = (sp.diags(1.0 / C) @ (-L)).tocsr()  # linear part of dT/dt
    A.sort_indices()
    kr = d["sigma"] * np.asarray(d["GR"], float) / C
    Ts4 = (d["T_sink"] + K) ** 4
    lin_src = gc * (d["T_air"] + K) / C
    breaks = sorted({t for h in d["heaters"] for t, _ in h["schedule"] if 0 < t < d["duration"]})

    def power(t):
        q = np.zeros(n)
        for h in d["heaters"]:
            v = 0.0
            for tk, vk in h["schedule"]:
                if t >= tk:
                    v = vk
            q[h["node"]] += v
        return q / C

    return dict(n=n, A=A, kr=kr, Ts4=Ts4, lin_src=lin_src, power=power, breaks=breaks,
                T0=np.asarray(d["T0"], float) + K, duration=d["duration"])


def solve(m, rtol, atol):
    A, kr, Ts4, lin_src = m["A"], m["kr"], m["Ts4"], m["lin_src"]
    pattern = (A + sp.identity(m["n"], format="csr")).astype(bool).tocsr()
    I = sp.identity(m["n"], format="csr")
    y = m["T0"].copy()
    bounds = [0.0] + m["breaks"] + [m["duration"]]
    stats = dict(nfev=0, njev=0, nlu=0)
    t0 = time.perf_counter()
    for t_a, t_b in zip(bounds[:-1], bounds[1:]):
        src = lin_src + m["power"](0.5 * (t_a + t_b))

        def f(t, T):
            return A @ T - kr * (T ** 4 - Ts4) + src

        def jac(t, T):
            return A - sp.diags(4.0 * kr * T ** 3, format="csr")

        r = solve_ivp(f, (t_a, t_b), y, method="BDF", rtol=rtol, atol=atol, jac=jac,
                      jac_sparsity=pattern)
        if not r.success:
            raise RuntimeError(r.message)
        y = r.y[:, -1].copy()
        for k in stats:
            stats[k] += getattr(r, k)
    wall = time.perf_counter() - t0
    return y - K, wall, stats


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("json")
    ap.add_argument("--rtol", type=float, default=1e-6)
    ap.add_argument("--atol", type=float, default=1e-6)
    ap.add_argument("--reference", action="store_true", help="rtol = atol = 1e-9")
    ap.add_argument("--out", help="write every node's final temperature (degC), one per line")
    a = ap.parse_args()
    if a.reference:
        a.rtol = a.atol = 1e-9
    with open(a.json) as fh:
        d = json.load(fh)
    m = assemble(d)
    T, wall, st = solve(m, a.rtol, a.atol)
    for k in d["probes"]:
        print(f"probe {d['names'][k]} {T[k]:.9f}")
    if a.out:
        np.savetxt(a.out, T, fmt="%.10f")
    print(f"stats nfev={st['nfev']} njev={st['njev']} nlu={st['nlu']} rtol={a.rtol:g} atol={a.atol:g}")
    print(f"wall_s {wall:.6f}")


if __name__ == "__main__":
    sys.exit(main())
