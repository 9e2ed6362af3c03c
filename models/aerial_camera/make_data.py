#!/usr/bin/python3
"""Regenerates data/case01.csv ... data/case11.csv: SYNTHETIC "measurements" of study A's camera.

THESE DATA ARE SYNTHETIC. They are not measurements of any camera. The "instrument" is this file:
its own description of the camera as hardware would differ from the model (camera.tnet), with
its own element physics and air properties, integrated by SciPy (solve_ivp, BDF); thermnet is
never run to make them. The truth differs from the model in everything a real camera would:

- the ranged params (k2 ... k16) at values inside the study's ranges, away from the initial
  ones (TRUE_PARAMS; calibration is meant to find these);
- every node's heat capacity off by a factor drawn once from U(0.8, 1.25) (the model's
  capacities are chosen, not measured; TRUE_CAPACITY_FACTORS);
- the correlation coefficients: the barrel gaps' Raithby-Hollands constant 0.386 -> 0.45, the
  window cavity's Catton Nu = 0.18 (..)^0.29 -> 0.20 (..)^0.27, the external convection
  5 -> 6 W/(m^2 K) (the model holds k10 fixed), the outside paint emissivity 0.85 -> 0.92;
- the contact conductance of the lens seats and the rear-cover mount, 2000 -> 800 W/(m^2 K);
- the window-barrel <-> lens-1 path the nominal network lacks, as convection plus radiation:
  air across the 2 mm gap between the window barrel's skirt and lens 1, h = 1.3 k_air(T) / gap
  (conduction plus a little convection, about 15 W/(m^2 K)) over 7.5e-3 m^2, and radiation from
  the skirt to the lens rim and face (the study's structure correction);
- sensor noise: Gaussian, sigma 0.2 K, numpy default_rng(seed 2025), written to 0.01 K.

Every 120 s (0 ... 10800 s, 91 samples) the 23 nodes (every node; the ambient boundary is not a
sensor) are written for each of the 11 heating conditions of cases.tnet.

  make_data.py                  write data/case01.csv ... case11.csv
  make_data.py --check THERMNET the same integrator with the model's own values and physics
                                (nominal params, capacities, correlations, no added path) against
                                `THERMNET simulate camera.tnet` in every case: the largest
                                difference must stay under 0.01 K (the two air-property fits
                                differ slightly); exits 1 otherwise
"""
import csv
import io
import math
import os
import re
import subprocess
import sys

import numpy as np
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline

HERE = os.path.dirname(os.path.abspath(__file__))
SIGMA = 0.2  # K, sensor noise
DT = 120.0  # s, sampling interval
SEED = 2025
SIGMA_SB = 5.670374419e-8
G = 9.80665
ZERO_C = 273.15
NODES = ["win_c", "win_e", "wbarrel", "wjoint",
         "lens1_c", "lens1_e", "lens2_c", "lens2_e", "lens3_c", "lens3_e", "lens4_c", "lens4_e",
         "barrel1", "barrel2", "barrel3", "barrel4", "iframe1", "iframe2", "oframe1", "oframe2",
         "rcover", "fjoint1", "fjoint2"]
AMBIENT = -38.5  # degC
# Nominal capacities, J/K (geometry.tnet's chosen values).
CAPACITY = {"win_c": 12, "win_e": 10, "wbarrel": 30, "wjoint": 5, "lens1_c": 200, "lens1_e": 90,
            "lens2_c": 90, "lens2_e": 90, "lens3_c": 90, "lens3_e": 90, "lens4_c": 90,
            "lens4_e": 90, "barrel1": 110, "barrel2": 110, "barrel3": 110, "barrel4": 110,
            "iframe1": 150, "iframe2": 150, "oframe1": 200, "oframe2": 200, "rcover": 150,
            "fjoint1": 5, "fjoint2": 5}

# ---- the truth ---------------------------------------------------------------------------------
TRUE_PARAMS = {"k1": 1.0, "k2": 105.0, "k5": 0.12, "k6": 0.15, "k7": 3.9, "k8": 2.5, "k10": 6.0,
               "k12": 0.05, "k14": 0.25, "k15": 40.0, "k16": 3.2}
TRUE_CAPACITY_FACTORS = dict(zip(NODES, np.round(np.random.default_rng(7).uniform(0.8, 1.25, len(NODES)), 3)))


class Physics:
    """What differs between the model's physics and the hardware's (the correlation constants,
    the contact conductance, the paint emissivity, whether the window-barrel path exists)."""

    def __init__(self, truth: bool):
        self.annulus_c = 0.45 if truth else 0.386       # Raithby-Hollands constant
        self.cavity = (0.20, 0.27) if truth else (0.18, 0.29)  # Catton, H/L < 2: Nu = a (..)^b
        self.h_contact = 800.0 if truth else 2000.0     # W/(m^2 K), lens seats and cover mount
        self.eps_paint = 0.92 if truth else 0.85
        self.link = truth                               # the window-barrel <-> lens-1 path


# ---- air (Incropera, Table A.4, 1 atm), a cubic spline of the table -----------------------------
_T = [150, 200, 250, 300, 350, 400]
_AIR = {"k": CubicSpline(_T, [13.8e-3, 18.1e-3, 22.3e-3, 26.3e-3, 30.0e-3, 33.8e-3]),
        "nu": CubicSpline(_T, [4.426e-6, 7.590e-6, 11.44e-6, 15.89e-6, 20.92e-6, 26.41e-6]),
        "alpha": CubicSpline(_T, [5.84e-6, 10.3e-6, 15.9e-6, 22.5e-6, 29.9e-6, 38.3e-6]),
        "Pr": CubicSpline(_T, [0.758, 0.737, 0.720, 0.707, 0.700, 0.690])}


def air(name: str, t_kelvin):
    return _AIR[name](np.clip(t_kelvin, 200.0, 400.0))


# ---- the network ---------------------------------------------------------------------------------
def network(p: dict, phys: Physics):
    """Links of the camera: lists of (a, b, value) per kind; b may be "ambient"."""
    pi = math.pi
    t_wall, d_barrel, d_inner, d_outer, l_barrel = 3e-3, 70e-3, 114e-3, 163e-3, 150e-3
    l_seg = l_barrel / 4
    d_lens, t_lens, t_rtv = 60e-3, 10e-3, 2e-3
    a_lens, a_win = pi * (d_lens / 2) ** 2, pi * 0.02 ** 2
    k1, k2 = p["k1"], p["k2"]
    lin, rad, annulus, cavity, gap_air = [], [], [], [], []

    def series(*g):
        return 1.0 / sum(1.0 / x for x in g)

    a_seat = pi * d_lens * t_lens
    for i in range(1, 5):
        lin.append((f"lens{i}_c", f"lens{i}_e", 2 * pi * k1 * t_lens / math.log(25 / 10)))
        lin.append((f"lens{i}_e", f"barrel{i}", series(k1 * a_seat / 5e-3, 0.2 * a_seat / t_rtv,
                                                       phys.h_contact * a_seat, k2 * a_seat / 5e-3)))
    for i in (1, 2, 3):
        rad.append((f"lens{i}_c", f"lens{i + 1}_c", 0.8 * a_lens / (1 / 0.9 + 1 / 0.9 - 1)))
    for i in (1, 2, 3):
        lin.append((f"barrel{i}", f"barrel{i + 1}", k2 * pi * d_barrel * t_wall / l_seg))
    lin.append(("iframe1", "iframe2", k2 * pi * d_inner * t_wall / (l_barrel / 2)))
    lin.append(("oframe1", "oframe2", k2 * pi * d_outer * t_wall / (l_barrel / 2)))
    eps_f = p["k12"]
    gr_ff = 1 / (1 / eps_f + 1 / eps_f - 1)
    for i, frame in ((1, "iframe1"), (2, "iframe1"), (3, "iframe2"), (4, "iframe2")):
        annulus.append((f"barrel{i}", frame, (d_barrel, d_inner, l_seg, p["k5"] / 0.09)))
        rad.append((f"barrel{i}", frame, pi * d_barrel * l_seg * gr_ff))
    for i in (1, 2):
        annulus.append((f"iframe{i}", f"oframe{i}", (d_inner, d_outer, l_barrel / 2, p["k6"] / 0.12)))
        rad.append((f"iframe{i}", f"oframe{i}", pi * d_inner * l_barrel / 2 * gr_ff))
    for a, j, b in (("barrel1", "fjoint1", "iframe1"), ("iframe2", "fjoint2", "oframe2"),
                    ("wbarrel", "wjoint", "barrel1")):
        lin.append((a, j, 2.0 / p["k15"]))
        lin.append((j, b, 2.0 / p["k15"]))
    lin.append(("barrel4", "rcover", p["k8"] * pi * (d_barrel / 2) ** 2))
    lin.append(("lens4_c", "rcover", p["k8"] * a_lens))
    lin.append(("rcover", "oframe2", series(phys.h_contact * 4e-4, k2 * 4e-4 / 10e-3)))
    a_wr = pi * 0.04 * 8e-3
    lin.append(("win_c", "win_e", k1 * a_wr / 10e-3))
    lin.append(("win_e", "wbarrel", series(k1 * a_wr / 3e-3, 1.0 / p["k16"])))
    cavity.append(("win_c", "lens1_c", (a_win, 36e-3, 40e-3, p["k7"] / 2.6)))
    rad.append(("win_c", "lens1_c", 0.6 * a_win / (1 / p["k14"] + 1 / 0.9 - 1)))
    h_out, eps_p = p["k10"], phys.eps_paint
    a_wb, a_of, a_rc = 0.005, pi * (d_outer + 10e-3) * l_barrel / 2, pi * (d_outer / 2) ** 2
    for node, area, eps in (("win_c", a_win, p["k14"]), ("wbarrel", a_wb, eps_f), ("oframe1", a_of, eps_p),
                            ("oframe2", a_of, eps_p), ("rcover", a_rc, eps_p)):
        lin.append((node, "ambient", h_out * area))
        rad.append((node, "ambient", area * eps))  # to surroundings at ambient, eps2 = 1
    if phys.link:
        a_skirt = pi * d_lens * 40e-3
        gap_air.append(("wbarrel", "lens1_c", (1.3 / 2e-3, a_skirt)))
        rad.append(("wbarrel", "lens1_e", 0.5 * a_skirt / (1 / eps_f + 1 / 0.9 - 1)))
        rad.append(("wbarrel", "lens1_c", 0.5 * a_win / (1 / eps_f + 1 / 0.9 - 1)))
    return lin, rad, annulus, cavity, gap_air


class Camera:
    """The heat balances C dT/dt = sum of flows + heaters, temperatures in kelvin."""

    def __init__(self, p: dict, phys: Physics, capacity_factors: dict):
        self.phys = phys
        idx = {n: i for i, n in enumerate(NODES)}
        self.n = len(NODES)
        self.C = np.array([CAPACITY[n] * capacity_factors.get(n, 1.0) for n in NODES])
        lin, rad, annulus, cavity, gap_air = network(p, phys)

        def ends(links):
            a = np.array([idx[x[0]] for x in links], dtype=int)
            b = np.array([idx.get(x[1], -1) for x in links], dtype=int)  # -1: ambient
            return a, b

        self.lin = (*ends(lin), np.array([x[2] for x in lin]))
        self.rad = (*ends(rad), np.array([x[2] for x in rad]) * SIGMA_SB)
        self.annulus = (*ends(annulus), [x[2] for x in annulus])
        self.cavity = (*ends(cavity), [x[2] for x in cavity])
        self.gap_air = (*ends(gap_air), [x[2] for x in gap_air])
        self.heated = np.array([idx[f"barrel{i}"] for i in range(1, 5)])

    def _flows(self, T, links, q_of):
        a, b, vals = links
        dq = np.zeros(self.n)
        t_amb = AMBIENT + ZERO_C
        for k, (ia, ib) in enumerate(zip(a, b)):
            ta, tb = T[ia], (T[ib] if ib >= 0 else t_amb)
            q = q_of(ta, tb, vals[k])
            dq[ia] -= q
            if ib >= 0:
                dq[ib] += q
        return dq

    def annulus_q(self, ta, tb, v):
        d_in, d_out, length, scale = v
        tm, dt = 0.5 * (ta + tb), ta - tb
        delta = 0.5 * (d_out - d_in)
        ln = math.log(d_out / d_in)
        k, nu, al, pr = (float(air(x, tm)) for x in ("k", "nu", "alpha", "Pr"))
        ra_d = G * abs(dt) * delta ** 3 / (tm * nu * al)
        ra_c = ln ** 4 / (delta ** 3 * (d_in ** -0.6 + d_out ** -0.6) ** 5) * ra_d
        x = self.phys.annulus_c * (pr / (0.861 + pr)) ** 0.25 * ra_c ** 0.25
        return scale * 2 * math.pi * k * (1 + x ** 8) ** 0.125 * length * dt / ln

    def cavity_q(self, ta, tb, v):
        area, gap, height, scale = v
        tm, dt = 0.5 * (ta + tb), ta - tb
        k, nu, al, pr = (float(air(x, tm)) for x in ("k", "nu", "alpha", "Pr"))
        ra = G * abs(dt) * gap ** 3 / (tm * nu * al)
        assert height / gap < 2  # Catton's eq. 9.53, the window cavity's aspect ratio
        a, b = self.phys.cavity
        nu_ = a * (pr / (0.2 + pr) * ra) ** b
        return scale * k * (1 + nu_ ** 8) ** 0.125 / gap * area * dt

    @staticmethod
    def gap_air_q(ta, tb, v):
        per_k, area = v  # h = per_k * k_air(Tm)
        return per_k * float(air("k", 0.5 * (ta + tb))) * area * (ta - tb)

    def rhs(self, t, T, power):
        a, b, g = self.lin
        t_amb = AMBIENT + ZERO_C
        tb = np.where(b >= 0, T[np.maximum(b, 0)], t_amb)
        q = g * (T[a] - tb)
        ar, br, gr = self.rad
        tbr = np.where(br >= 0, T[np.maximum(br, 0)], t_amb)
        qr = gr * (T[ar] ** 4 - tbr ** 4)
        dq = np.zeros(self.n)
        np.add.at(dq, a, -q)
        np.add.at(dq, b[b >= 0], q[b >= 0])
        np.add.at(dq, ar, -qr)
        np.add.at(dq, br[br >= 0], qr[br >= 0])
        dq += self._flows(T, self.annulus, self.annulus_q)
        dq += self._flows(T, self.cavity, self.cavity_q)
        dq += self._flows(T, self.gap_air, self.gap_air_q)
        dq[self.heated] += power / 4
        return dq / self.C

    def run(self, p_heat: float, t_off: float, times: np.ndarray) -> np.ndarray:
        """Temperatures (degC) at `times`, starting soaked at the ambient; heating until t_off."""
        T0 = np.full(self.n, AMBIENT + ZERO_C)
        out = np.empty((len(times), self.n))
        for (t0, t1, power) in ((0.0, t_off, p_heat), (t_off, times[-1], 0.0)):
            keep = (times >= t0) & (times < t1)
            t_eval = np.append(times[keep], t1)  # the end state starts the next stretch
            sol = solve_ivp(self.rhs, (t0, t1), T0, method="BDF", t_eval=t_eval, args=(power,),
                            rtol=1e-9, atol=1e-7, first_step=1e-2)
            if not sol.success:
                sys.exit(f"make_data.py: integration failed: {sol.message}")
            out[keep] = sol.y[:, :-1].T
            T0 = sol.y[:, -1]
        out[-1] = T0  # times[-1] is the end of the second stretch
        return out - ZERO_C


def cases() -> list[tuple[str, float, float]]:
    """(name, P_heat W, t_off s) of the 11 heating conditions, read from cases.tnet."""
    rows = []
    for line in open(os.path.join(HERE, "cases.tnet")):
        m = re.match(r"case (case\d+) .*P_heat = ([0-9.]+) \[W\] ; t_off = ([0-9.]+) \[s\]", line)
        if m:
            rows.append((m.group(1), float(m.group(2)), float(m.group(3))))
    assert len(rows) == 11, rows
    return rows


def nominal_params() -> dict:
    """The model's declared values of k1 ... k16 (params_nominal.tnet; coherent SI units)."""
    p = {}
    for line in open(os.path.join(HERE, "params_nominal.tnet")):
        m = re.match(r"param (k\d+)\s*=\s*([-+0-9.eE]+)", line)
        if m:
            p[m.group(1)] = float(m.group(2))
    return p


def check(thermnet: str) -> int:
    camera = Camera(nominal_params(), Physics(truth=False), {})
    worst = 0.0
    for name, p_heat, t_off in cases():
        out = subprocess.run([thermnet, "simulate", os.path.join(HERE, "camera.tnet"), "--case", name],
                             check=True, capture_output=True, text=True).stdout
        rows = list(csv.DictReader(io.StringIO(out)))
        t = np.array([float(r["time"]) for r in rows])
        ref = np.array([[float(r[n]) for n in NODES] for r in rows])
        diff = np.max(np.abs(camera.run(p_heat, t_off, t) - ref))
        worst = max(worst, diff)
        print(f"{name}: SciPy vs thermnet, nominal model: largest difference {diff:.4f} K")
    ok = worst < 0.01
    print(f"{'ok' if ok else 'FAIL'}: largest difference {worst:.4f} K (limit 0.01 K)")
    return 0 if ok else 1


def main() -> int:
    if len(sys.argv) == 3 and sys.argv[1] == "--check":
        return check(sys.argv[2])
    if len(sys.argv) != 1:
        sys.exit(__doc__)
    camera = Camera(TRUE_PARAMS, Physics(truth=True), TRUE_CAPACITY_FACTORS)
    rng = np.random.default_rng(SEED)
    grid = np.arange(0.0, 10800.0 + 1e-6, DT)
    os.makedirs(os.path.join(HERE, "data"), exist_ok=True)
    for name, p_heat, t_off in cases():
        T = camera.run(p_heat, t_off, grid)
        path = os.path.join(HERE, "data", f"{name}.csv")
        with open(path + ".tmp", "w", newline="") as f:
            f.write("time," + ",".join(NODES) + "\n")
            for k, tk in enumerate(grid):
                vals = T[k] + rng.normal(0.0, SIGMA, len(NODES))
                f.write(f"{tk:g}," + ",".join(f"{v:.2f}" for v in vals) + "\n")
        os.replace(path + ".tmp", path)
        print(f"wrote data/{name}.csv ({len(grid)} samples x {len(NODES)} nodes, SYNTHETIC)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
