#!/usr/bin/python3
"""A one-room test building, simulated by SciPy: the truth that issue 50's building test diagnoses.

The structure is the one published for a heated test building identified from PRBS heating
experiments (Bacher & Madsen, "Identifying suitable models for the heat dynamics of buildings",
Energy and Buildings 43 (2011) 1511-1522, the TiTeThTs model and its solar split):

- Ti  the room air (capacity Ci), the node a user's first model has;
- Te  the envelope, a mass inside the link from the room to the outdoor air (Rie to the room,
      Rea to the outdoors);
- Th  the heater's own mass (Rih to the room), into which the heater's power goes;
- Ts  the sensor node (Ris to the room, capacity Cs): what the thermometer reads;
- solar gain Aw * I into the room and Ae * I into the envelope.

What a real building has beside the structure, and the model does not: an unmeasured heat input
into the room (occupants, ventilation; an Ornstein-Uhlenbeck process of 120 W spread and 1 h
correlation time), so that no structure reaches the measurement noise, and AR(1) measurement
noise (0.05 K spread, lag-1 correlation 0.7 at 5 min). The inputs look like measured ones: the
heater a pseudo-random binary sequence (on 2.8 kW or off, held 30 min to 4 h), the outdoor air a
daily cycle with weather drift, the global irradiance a clear-sky day under drifting clouds.

The states are integrated by SciPy's solve_ivp (LSODA, max step 60 s) over the inputs linear
between the 5-minute samples (as the data file gives them), the disturbance held over each
minute; an independent simulator of the same physics, not thermnet.

Usage as a module: generate(seed) -> dict of arrays; fit_truth(data) -> output-error fit of the
true structure (SciPy least squares, every R, C and A free and the envelope's start).
"""
import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import expm
from scipy.optimize import least_squares

STEP = 300.0            # s, the sampling interval
HOURS = 140             # the record's length
TRUTH = dict(Ci=6.0e5, Ce=1.2e7, Ch=8.0e5, Cs=5.0e4,      # J/K
             Gie=1100.0, Gea=222.0, Gih=1560.0, Gis=130.0,  # W/K
             Aw=5.75, Ae=3.87)                              # m^2
P_ON = 2800.0           # W, the heater when on
DIST_SD = 120.0         # W, the spread of the unmeasured heat input into the room


def ou(rng, n, dt, tau, sd):
    """An Ornstein-Uhlenbeck series of n samples dt apart: spread sd, correlation time tau."""
    a = np.exp(-dt / tau)
    x = np.empty(n)
    x[0] = rng.normal(0, sd)
    e = rng.normal(0, sd * np.sqrt(1 - a * a), n)
    for k in range(1, n):
        x[k] = a * x[k - 1] + e[k]
    return x


def inputs(rng):
    """Sample times and the measured inputs: outdoor air (degC), heater power (W), irradiance."""
    n = int(HOURS * 3600 / STEP) + 1
    t = np.arange(n) * STEP
    hour = t / 3600.0
    To = 4.0 + 3.0 * np.sin(2 * np.pi * (hour - 9.0) / 24.0) + ou(rng, n, STEP, 12 * 3600, 2.0)
    # PRBS: each state held a random multiple of 30 min (1 to 8 of them).
    Qh = np.zeros(n)
    k, on = 0, rng.random() < 0.5
    while k < n:
        hold = int(rng.integers(1, 9)) * 6
        Qh[k:k + hold] = P_ON if on else 0.0
        k, on = k + hold, not on
    # Clear sky between 7 h and 17 h (a winter day), under clouds drifting over an hour.
    day = (hour % 24.0 - 7.0) / 10.0
    clear = np.where((day > 0) & (day < 1), 450.0 * np.sin(np.pi * np.clip(day, 0, 1)), 0.0)
    cloud = np.clip(0.6 + ou(rng, n, STEP, 3600.0, 0.35), 0.1, 1.0)
    I = clear * cloud
    return t, To, Qh, I


def rhs_matrices(p):
    """x' = A x + B u for x = (Ti, Te, Th, Ts), u = (To, Qh, I, disturbance W into Ti)."""
    Ci, Ce, Ch, Cs = p["Ci"], p["Ce"], p["Ch"], p["Cs"]
    Gie, Gea, Gih, Gis = p["Gie"], p["Gea"], p["Gih"], p["Gis"]
    A = np.array([
        [-(Gie + Gih + Gis) / Ci, Gie / Ci, Gih / Ci, Gis / Ci],
        [Gie / Ce, -(Gie + Gea) / Ce, 0.0, 0.0],
        [Gih / Ch, 0.0, -Gih / Ch, 0.0],
        [Gis / Cs, 0.0, 0.0, -Gis / Cs]])
    B = np.array([
        [0.0, 0.0, p["Aw"] / Ci, 1.0 / Ci],
        [Gea / Ce, 0.0, p["Ae"] / Ce, 0.0],
        [0.0, 1.0 / Ch, 0.0, 0.0],
        [0.0, 0.0, 0.0, 0.0]])
    return A, B


def steady(p, u):
    A, B = rhs_matrices(p)
    return np.linalg.solve(A, -B @ u)


def generate(seed=50):
    rng = np.random.default_rng(seed)
    t, To, Qh, I = inputs(rng)
    minutes = np.arange(0, t[-1] + 60.0, 60.0)
    dist = ou(rng, minutes.size, 60.0, 3600.0, DIST_SD)
    A, B = rhs_matrices(TRUTH)

    def u_at(s):
        d = dist[min(int(s // 60.0), dist.size - 1)]
        return np.array([np.interp(s, t, To), np.interp(s, t, Qh), np.interp(s, t, I), d])

    # The building has been heated on and off for days before the record: it starts from the
    # steady state of the first day's mean inputs, not in equilibrium with the first sample.
    day = t < 24 * 3600
    x0 = steady(TRUTH, np.array([To[day].mean(), Qh[day].mean(), I[day].mean(), 0.0]))
    sol = solve_ivp(lambda s, x: A @ x + B @ u_at(s), (0.0, t[-1]), x0, method="LSODA",
                    t_eval=t, max_step=60.0, rtol=1e-8, atol=1e-8)
    if not sol.success:
        raise RuntimeError(sol.message)
    X = sol.y.T
    # AR(1) measurement noise on the sensor node.
    phi, sd = 0.7, 0.05
    e = np.empty(t.size)
    e[0] = rng.normal(0, sd)
    w = rng.normal(0, sd * np.sqrt(1 - phi * phi), t.size)
    for k in range(1, t.size):
        e[k] = phi * e[k - 1] + w[k]
    y = np.round(X[:, 3] + e, 2)  # a logger's 0.01 K resolution
    return dict(t=t, To=To, Qh=Qh, I=I, y=y, states=X, x0=x0)


def _discrete(A, B, h):
    n, m = B.shape
    M = np.zeros((n + 2 * m, n + 2 * m))
    M[:n, :n], M[:n, n:n + m], M[n:n + m, n + m:] = A * h, B * h, np.eye(m)
    E = expm(M)
    return E[:n, :n], E[:n, n:n + m], E[:n, n + m:]


def simulate_sampled(p, t, U, x0, out=3):
    """State `out` at the samples of the linear model, exact for inputs linear between them."""
    A, B = rhs_matrices(p)
    Ad, B0, B1 = _discrete(A, B, t[1] - t[0])
    x, ys = np.array(x0, float), [x0[out]]
    G = B0 - B1
    for k in range(t.size - 1):
        x = Ad @ x + G @ U[k] + B1 @ U[k + 1]
        ys.append(x[out])
    return np.array(ys)


NAMES = ["Ci", "Ce", "Ch", "Cs", "Gie", "Gea", "Gih", "Gis"]


def fit_truth(d, structure="full"):
    """Output-error fit of a structure to the data (SciPy least squares on the exact
    discretisation), every capacity, conductance and solar aperture free and the envelope's
    start; the room and the sensor start at the first reading, the heater in equilibrium with it.
    structure: "full" (the truth's), "envelope" (the room and its envelope: Th and Ts negligible)
    or "one" (the room alone). Several starts; the best fit is returned as (rmse, params)."""
    t, y = d["t"], d["y"]
    U = np.column_stack([d["To"], d["Qh"], d["I"], np.zeros(t.size)])

    def unpack(z):
        p = dict(zip(NAMES + ["Aw", "Ae"], np.concatenate([np.exp(z[:8]), z[8:10]])))
        if structure in ("envelope", "one"):  # negligible masses, tightly linked
            p["Ch"], p["Gih"], p["Cs"], p["Gis"] = 1.0, 1e6, 1.0, 1e6
        if structure == "one":
            p["Ce"], p["Gie"] = 1.0, 1e6
        return p, z[10]

    def resid(z):
        p, te0 = unpack(z)
        x0 = np.array([y[0], te0, y[0] + d["Qh"][0] / p["Gih"], y[0]])
        return simulate_sampled(p, t, U, x0) - y

    def start(**kw):
        p = dict(TRUTH, Te0=y[0] - 3.0)
        p.update(kw)
        return np.concatenate([np.log([p[k] for k in NAMES]), [p["Aw"], p["Ae"], p["Te0"]]])

    lumped = TRUTH["Ci"] + TRUTH["Ch"] + TRUTH["Cs"]
    starts = {"full": [start(), start(Ci=2 * TRUTH["Ci"], Ce=0.5 * TRUTH["Ce"])],
              "envelope": [start(Ci=lumped), start(Ci=2e6, Ce=6e6)],
              "one": [start(Ci=5e6), start(Ci=2e7)]}[structure]
    best = None
    for z0 in starts:
        with np.errstate(over="ignore", invalid="ignore"):
            r = least_squares(resid, z0, x_scale="jac", max_nfev=3000)
        if best is None or r.cost < best.cost:
            best = r
    p, te0 = unpack(best.x)
    p["Te0"] = te0
    return float(np.sqrt(np.mean(best.fun ** 2))), p


if __name__ == "__main__":
    d = generate()
    print("samples", d["t"].size, "Ti range", d["states"][:, 0].min(), d["states"][:, 0].max(),
          "To range", d["To"].min(), d["To"].max())
    U = np.column_stack([d["To"], d["Qh"], d["I"], np.zeros(d["t"].size)])
    at = simulate_sampled(TRUTH, d["t"], U, d["x0"])
    print("truth params, true start, no disturbance: RMSE", np.sqrt(np.mean((at - d["y"]) ** 2)))
    for s in ("one", "envelope", "full"):
        r, p = fit_truth(d, s)
        print(s, "OE RMSE", round(r, 4), {k: float(f"{v:.4g}") for k, v in p.items()})
