#!/usr/bin/python3
"""Measured data for the external diagnosis test, made WITHOUT thermnet.

Each network below is typed by hand (independently of rod.tnet / star.tnet), integrated with
scipy's solve_ivp (BDF, rtol = atol = 1e-10, restarted at every heater or boundary corner) and
sampled at the output times with Gaussian sensor noise. An optional hidden effect -- one the .tnet
file does not describe -- is added to the network or to the sensors first.

Usage: make_data.py OUTDIR EFFECT [SEED]
  EFFECT: rod_clean | rod_radiation (a3 radiates to the sky, GR = 0.01 m^2)
          rod_mass (the film heats a1 through a mass of its own: 400 J/K, 0.8 W/K to a1)
          rod_lid (a3 loses 0.5 W/K to the sky only while the lid is open; events.csv)
          star_clean | star_source (hub gains 4 W) | star_offset (arm3 sensor reads +0.7 K) |
          star_lag (arm2's sensor lags it with tau = 150 s)
"""
import sys

import numpy as np
from scipy.integrate import solve_ivp

SIGMA = 0.05  # K, sensor noise
# When the rod's lid was open, as a user would list it for `thermnet diagnose --events`: per case,
# and (empty case) in every case.
LID = [("slow", 1500, 2700), ("pulse", 3000, 4200), ("", 7000, 7600)]
SB = 5.670374419e-8
ZERO_C = 273.15


def step(points):
    """step(t0: v0, t1: v1, ...): v_i from t_i on."""
    return lambda t: next(v for (ti, v) in reversed(points) if t >= ti or ti == points[0][0])


def pwl(points):
    """pwl(t0: v0, ...): linear between the points, constant outside."""
    ts, vs = zip(*points)
    return lambda t: float(np.interp(t, ts, vs))


def rod(case, hidden):
    nodes = ["a1", "a2", "a3", "a4", "a5"]
    C = [900.0, 700.0, 700.0, 600.0, 500.0]
    links = [(0, 1, 1.8), (1, 2, 1.4), (2, 3, 1.2), (3, 4, 1.0)]
    wall, sky = 15.0, -40.0
    if case == "slow":
        film, corners = step([(0, 25.0), (3000, 0.0)]), [3000]
    else:
        film = step([(0, 0.0), (1200, 40.0), (2400, 0.0), (5400, 15.0)])
        corners = [1200, 2400, 5400]
    rad_a3 = 0.01 if hidden == "radiation" else 0.0
    lid_g = 0.5 if hidden == "lid" else 0.0
    lid = [(a, b) for c, a, b in LID if c in ("", case)]
    corners = sorted(corners + [t for w in lid for t in w])
    heated = 5 if hidden == "mass" else 0  # the film heats a mass node (index 5) linked to a1
    if heated:
        C = C + [400.0]
        links = links + [(5, 0, 0.8)]

    def rhs(t, T):
        q = np.zeros(len(C))
        for a, b, g in links:
            f = g * (T[b] - T[a])
            q[a] += f
            q[b] -= f
        q[4] += 0.9 * (wall - T[4])
        q[4] += 0.004 * SB * ((sky + ZERO_C) ** 4 - (T[4] + ZERO_C) ** 4)
        q[2] += rad_a3 * SB * ((sky + ZERO_C) ** 4 - (T[2] + ZERO_C) ** 4)
        if any(a <= t < b for a, b in lid):
            q[2] += lid_g * (sky - T[2])
        q[heated] += film(t)
        return q / np.array(C)

    return nodes, [15.0] * len(C), rhs, corners, 9000.0, 60.0


def star(hidden):
    nodes = ["hub", "arm1", "arm2", "arm3", "arm4"]
    C = [1500.0, 400.0, 350.0, 450.0, 300.0]
    arm = [0.9, 0.7, 1.1, 0.8]
    out = [0.2, 0.35, 0.3, 0.4, 0.25]
    air = pwl([(0, 22.0), (7200, 12.0)])
    pad = pwl([(0, 0.0), (1800, 30.0), (3600, 30.0), (4200, 0.0)])
    source = 4.0 if hidden == "source" else 0.0
    tau = 150.0  # star_lag: arm2's sensor reads through a first-order lag, R' = (T - R) / tau

    def rhs(t, T):
        q = np.zeros(len(T))
        for i, g in enumerate(arm):
            f = g * (T[i + 1] - T[0])
            q[0] += f
            q[i + 1] -= f
        for i, g in enumerate(out):
            q[i] += g * (air(t) - T[i])
        q[2] += pad(t)
        q[0] += source
        rates = q[:5] / np.array(C)
        if hidden == "lag":
            rates = np.append(rates, (T[2] - T[5]) / tau)
        return rates

    T0 = [22.0] * (6 if hidden == "lag" else 5)
    return nodes, T0, rhs, [1800, 3600, 4200], 7200.0, 30.0


def simulate(net):
    nodes, T0, rhs, corners, end, dt = net
    times = np.arange(0.0, end + dt / 2, dt)
    edges = [0.0] + [c for c in corners if 0 < c < end] + [end]
    T, out = np.array(T0), []
    for a, b in zip(edges[:-1], edges[1:]):
        ev = times[(times >= a) & (times < b)] if b < end else times[times >= a]
        sol = solve_ivp(rhs, (a, b), T, method="BDF", t_eval=ev, rtol=1e-10, atol=1e-10)
        assert sol.success, sol.message
        out.append(sol.y.T)
        T = solve_ivp(rhs, (a, b), T, method="BDF", rtol=1e-10, atol=1e-10).y[:, -1]
    temps = np.vstack(out)
    if len(T0) > len(nodes) and nodes[0] == "hub":  # star_lag: arm2 is read through its lag
        temps[:, 2] = temps[:, 5]
    return nodes, times, temps[:, : len(nodes)]  # hidden nodes are not measured


def write(path, nodes, times, temps, rng, offsets=None):
    temps = temps + rng.normal(0.0, SIGMA, temps.shape)
    for i, extra in (offsets or {}).items():
        temps[:, i] += extra
    with open(path, "w") as f:
        f.write("time," + ",".join(nodes) + "\n")
        for t, row in zip(times, temps):
            f.write(f"{t:g}," + ",".join(f"{v:.4f}" for v in row) + "\n")


def main():
    outdir, effect = sys.argv[1], sys.argv[2]
    rng = np.random.default_rng(int(sys.argv[3]) if len(sys.argv) > 3 else 5)
    net, hidden = effect.split("_")
    if net == "rod":
        for case in ("slow", "pulse"):
            write(f"{outdir}/rod_{case}.csv", *simulate(rod(case, hidden)), rng)
        with open(f"{outdir}/events.csv", "w") as f:  # the lid was opened in every rod effect
            f.write("case,event,start,end\n")
            f.writelines(f"{c},lid,{a},{b}\n" for c, a, b in LID)
    else:
        offsets = {3: 0.7} if hidden == "offset" else None
        write(f"{outdir}/star_run.csv", *simulate(star(hidden)), rng, offsets)


if __name__ == "__main__":
    main()
