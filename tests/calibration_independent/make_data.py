#!/usr/bin/python3
"""Measured data for the independent calibration test, from a solver that shares nothing with
thermnet: an avionics box in a thermal-vacuum test, written out by hand as four ODEs (heat
balances in kelvin) and integrated by scipy's solve_ivp (BDF, rtol = atol = 1e-10, restarted at
every heater step and cold-plate knot), plus Gaussian noise of known sigma from a fixed seed.

Usage: make_data.py OUTDIR   writes OUTDIR/soak.csv, OUTDIR/cycle.csv and OUTDIR/truth.json
"""
import json
import sys

import numpy as np
from scipy.integrate import solve_ivp

SIGMA_SB = 5.670374419e-8  # W/(m^2 K^4)
ZERO_C = 273.15
NOISE = 0.15  # K, standard deviation of the measurement noise
DT = 60.0  # s between measurements

# The values that generate the data (SI); box.tnet declares them 2-3x off.
TRUTH = {"k_pad": 3.0, "h_ct": 400.0, "eps_cover": 0.35, "C_housing": 1600.0}

# Fixed data of the box (the same numbers box.tnet states in its own units).
C_PCB, C_COVER, C_BRACKET = 420.0, 350.0, 90.0  # J/K
A_PAD, L_PAD = 12e-4, 1.5e-3  # thermal pad, m^2 and m
A_CT = 40e-4  # housing / cold plate contact, m^2
R_HC = 1.1  # housing / cover screws, K/W
A_COVER = 0.06  # cover seen by the shroud, m^2 (shroud emissivity 1)
A_IN, EPS_IN = 0.02, 0.8  # pcb / cover internal radiation, both sides EPS_IN
G_BH = 0.5  # bracket / housing, W/K
A_BR, EPS_BR = 0.01, 0.9  # bracket seen by the shroud
T_SHROUD = -40.0  # degC

# Two experiments: heater steps (t: W), cold-plate temperature knots (t: degC), start temperature.
CASES = {
    "soak": {"heater": [(0, 25.0), (5400, 8.0)], "plate": [(0, 15.0)], "t0": 15.0, "end": 10800},
    "cycle": {"heater": [(0, 10.0), (1800, 30.0), (4500, 0.0)],
              "plate": [(0, 15.0), (3600, -5.0)], "t0": 20.0, "end": 9000},
}


def step(points, t):
    v = points[0][1]
    for tk, vk in points:
        if t >= tk:
            v = vk
    return v


def pwl(points, t):
    ts = [p[0] for p in points]
    vs = [p[1] for p in points]
    return float(np.interp(t, ts, vs))


def rhs(t, T, case):
    pcb, housing, cover, bracket = T
    p = TRUTH
    shroud = T_SHROUD + ZERO_C
    plate = pwl(case["plate"], t) + ZERO_C
    q_pad = p["k_pad"] * A_PAD / L_PAD * (pcb - housing)
    q_ct = p["h_ct"] * A_CT * (housing - plate)
    q_hc = (housing - cover) / R_HC
    q_in = SIGMA_SB * A_IN / (2.0 / EPS_IN - 1.0) * (pcb**4 - cover**4)
    q_out = SIGMA_SB * A_COVER * p["eps_cover"] * (cover**4 - shroud**4)
    q_bh = G_BH * (bracket - housing)
    q_br = SIGMA_SB * A_BR * EPS_BR * (bracket**4 - shroud**4)
    heater = step(case["heater"], t)
    return [
        (heater - q_pad - q_in) / C_PCB,
        (q_pad - q_ct - q_hc + q_bh) / p["C_housing"],
        (q_hc + q_in - q_out) / C_COVER,
        (-q_bh - q_br) / C_BRACKET,
    ]


def solve(case):
    times = np.arange(0.0, case["end"] + DT / 2, DT)
    breaks = sorted({0.0, float(case["end"])} | {float(t) for t, _ in case["heater"] + case["plate"]
                                                  if 0 < t < case["end"]})
    y = np.full(4, case["t0"] + ZERO_C)
    out = np.empty((len(times), 4))
    out[0] = y
    for a, b in zip(breaks[:-1], breaks[1:]):
        inside = (times > a) & (times <= b)
        t_eval = times[inside]
        if len(t_eval) == 0 or t_eval[-1] != b:
            t_eval = np.append(t_eval, b)  # the state at the break starts the next segment
        sol = solve_ivp(rhs, (a, b), y, method="BDF", t_eval=t_eval, args=(case,),
                        rtol=1e-10, atol=1e-10)
        if not sol.success:
            raise SystemExit(f"solve_ivp failed: {sol.message}")
        out[inside] = sol.y[:, :np.count_nonzero(inside)].T
        y = sol.y[:, -1]
    return times, out - ZERO_C


def main():
    outdir = sys.argv[1]
    rng = np.random.default_rng(20240611)
    for name, case in CASES.items():
        times, temps = solve(case)
        with open(f"{outdir}/{name}.csv", "w") as f:
            f.write("time,pcb,housing,cover\n")
            for t, row in zip(times, temps):
                noisy = row[:3] + rng.normal(0.0, NOISE, 3)
                f.write(f"{t:g}," + ",".join(f"{v:.4f}" for v in noisy) + "\n")
    with open(f"{outdir}/truth.json", "w") as f:
        json.dump({"params": TRUTH, "sigma": NOISE}, f, indent=2)


if __name__ == "__main__":
    main()
