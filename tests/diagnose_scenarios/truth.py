"""The independent truth: a Network integrated by SciPy (never by thermnet).

Heat balances C_i dT_i/dt = sum of flows + sources, radiation in kelvin, solve_ivp BDF with an
analytic Jacobian and tight tolerances, restarted at every corner of an input (a step, a pwl knot,
an event's start or end) with the step values frozen on each stretch, so no step is smeared.
A sensor with a first-order lag is one more state, dS/dt = (T - S) / tau.
"""
from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from network import SIGMA_SB, ZERO_C, Case, Network, capacity, conductance

RTOL = 1e-9
ATOL = 1e-9


class _Assembled:
    """The network's matrices at fixed param values, for one case."""

    def __init__(self, net: Network, params: dict[str, float], case: Case, lags: dict[str, float]):
        self.case = case
        names = [n.name for n in net.nodes]
        self.index = {n: i for i, n in enumerate(names)}
        self.bindex = {b.name: i for i, b in enumerate(net.boundaries)}
        n, nb = len(names), len(net.boundaries)
        self.n = n
        self.C = np.array([capacity(nd, params) for nd in net.nodes])
        self.K = np.zeros((n, n))  # node-node linear links
        self.Kb = np.zeros((n, nb))  # node-boundary linear links
        self.event_links: list[tuple[str, np.ndarray, np.ndarray]] = []
        rad = []  # (i, j, is_boundary_j, GR)
        for lk in net.links:
            g = conductance(lk, params)
            a, b = lk.a, lk.b
            if a not in self.index:
                a, b = b, a
            i = self.index[a]
            jb = b not in self.index
            j = self.bindex[b] if jb else self.index[b]
            if lk.kind == "radiation":
                rad.append((i, j, jb, g))
                continue
            K, Kb = np.zeros((n, n)), np.zeros((n, nb))
            K[i, i] -= g
            if jb:
                Kb[i, j] += g
            else:
                K[i, j] += g
                K[j, j] -= g
                K[j, i] += g
            if lk.during_event:
                self.event_links.append((lk.during_event, K, Kb))
            else:
                self.K += K
                self.Kb += Kb
        self.rad_i = np.array([r[0] for r in rad], dtype=int)
        self.rad_j = np.array([r[1] for r in rad], dtype=int)
        self.rad_jb = np.array([r[2] for r in rad], dtype=bool)
        self.rad_g = SIGMA_SB * np.array([r[3] for r in rad], dtype=float)
        self.H = np.zeros((n, len(net.heaters)))
        for k, h in enumerate(net.heaters):
            self.H[self.index[h.node], k] = 1.0
        self.heaters = [h.name for h in net.heaters]
        self.boundaries = [b.name for b in net.boundaries]
        self.lag_nodes = list(lags)
        self.lag_i = np.array([self.index[a] for a in lags], dtype=int)
        self.lag_tau = np.array([lags[a] for a in lags], dtype=float)

    def stretch(self, t_mid: float):
        """rhs and Jacobian on a stretch without corners (steps and events frozen at t_mid)."""
        c = self.case
        K, Kb = self.K.copy(), self.Kb.copy()
        for name, Ke, Kbe in self.event_links:
            if any(s <= t_mid < e for ev, s, e in c.events if ev == name):
                K += Ke
                Kb += Kbe
        steps_b = {b: s.at(t_mid) for b, s in c.boundary_T.items() if s.kind != "pwl"}
        steps_h = {h: s.at(t_mid) for h, s in c.heater_P.items() if s.kind != "pwl"}
        n, nl = self.n, len(self.lag_i)
        invC = 1.0 / self.C

        def inputs(t):
            Tb = np.array([steps_b[b] if b in steps_b else c.boundary_T[b].at(t) for b in self.boundaries])
            P = np.array([steps_h[h] if h in steps_h else c.heater_P[h].at(t) for h in self.heaters])
            return Tb, P

        def rhs(t, y):
            T = y[:n]
            Tb, P = inputs(t)
            q = K @ T + Kb @ Tb + self.H @ P
            if self.rad_g.size:
                Ti = T[self.rad_i] + ZERO_C
                Tj = np.empty_like(Ti)
                Tj[self.rad_jb] = Tb[self.rad_j[self.rad_jb]]
                Tj[~self.rad_jb] = T[self.rad_j[~self.rad_jb]]
                Tj += ZERO_C
                f = self.rad_g * (Tj**4 - Ti**4)  # into i
                np.add.at(q, self.rad_i, f)
                inner = ~self.rad_jb
                np.add.at(q, self.rad_j[inner], -f[inner])
            dy = np.empty(n + nl)
            dy[:n] = q * invC
            if nl:
                dy[n:] = (T[self.lag_i] - y[n:]) / self.lag_tau
            return dy

        def jac(t, y):
            T = y[:n]
            J = np.zeros((n + nl, n + nl))
            A = K.copy()
            if self.rad_g.size:
                Ti = T[self.rad_i] + ZERO_C
                d_i = 4.0 * self.rad_g * Ti**3
                np.add.at(A, (self.rad_i, self.rad_i), -d_i)
                for k in np.nonzero(~self.rad_jb)[0]:
                    i, j = self.rad_i[k], self.rad_j[k]
                    d_j = 4.0 * self.rad_g[k] * (T[j] + ZERO_C) ** 3
                    A[i, j] += d_j
                    A[j, j] -= d_j
                    A[j, i] += d_i[k]
            J[:n, :n] = A * invC[:, None]
            for k, (i, tau) in enumerate(zip(self.lag_i, self.lag_tau)):
                J[n + k, i] = 1.0 / tau
                J[n + k, n + k] = -1.0 / tau
            return J

        return rhs, jac


def simulate(net: Network, params: dict[str, float], case: Case, lags: dict[str, float] | None = None):
    """Integrates one case. Returns (times, T[time, node] in degC for net.nodes in order,
    {lagged node: its sensor's reading})."""
    lags = lags or {}
    asm = _Assembled(net, params, case, lags)
    end, dt = case.duration, case.output
    times = np.arange(0.0, end + dt / 2, dt)
    corners = {0.0, end}
    for s in list(case.boundary_T.values()) + list(case.heater_P.values()):
        corners.update(t for t in s.corners() if 0.0 < t < end)
    for _, s, e in case.events:
        corners.update(t for t in (s, e) if 0.0 < t < end)
    edges = sorted(corners)
    y = np.full(asm.n + len(lags), case.initial, dtype=float)
    rows = np.empty((len(times), asm.n + len(lags)))
    rows[0] = y
    for a, b in zip(edges[:-1], edges[1:]):
        rhs, jac = asm.stretch(0.5 * (a + b))
        inside = np.nonzero((times > a) & (times <= b))[0]
        t_eval = np.union1d(times[inside], [b])
        sol = solve_ivp(rhs, (a, b), y, method="BDF", t_eval=t_eval, jac=jac, rtol=RTOL, atol=ATOL)
        if not sol.success:
            raise RuntimeError(f"{net.name}/{case.name}: solve_ivp failed on [{a}, {b}]: {sol.message}")
        rows[inside] = sol.y[:, np.searchsorted(sol.t, times[inside])].T
        y = sol.y[:, -1]
    T = rows[:, : asm.n]
    sensors = {a: rows[:, asm.n + k] for k, a in enumerate(asm.lag_nodes)}
    return times, T, sensors
