#!/usr/bin/python3
"""Issue 50: the false-finding rate of `thermnet diagnose` (output error) on null cases.

A null case is data whose true structure is exactly the model's: SciPy simulates a small network
(exact discretisation with scipy.linalg.expm of the linear network, inputs linear between the
samples where the model reads them linearly and held where it reads them held), adds AR(1)
measurement noise (0.02-0.1 K spread, lag-1 correlation 0.5-0.9) and rounds to a logger's
0.01 K. The model handed to thermnet has the same nodes, links and sources, every capacity,
conductance, resistance and solar aperture declared as `param ... range LO .. HI` and started
20-50 % away from the truth. Only recalibrating the params can be right: any finding of another
kind than `parameter` is a false finding.

Families (one drawn per case, parameters, sampling, length and noise drawn too):
- building: a room and its envelope inside the link to the outdoors (2R2C), a pseudo-random
  binary heater, a daily outdoor cycle with weather drift, solar gain through apertures into the
  room and the envelope under drifting clouds; the envelope's start is fitted (`Te.T0 range`),
  the truth starts from days of heating before the record.
- rig2, rig3, rig4: lab rigs of 2-4 nodes (heater block, plates), a PRBS heater, a room whose
  recorded temperature drifts; one or more nodes measured; they start at the room's temperature.
- lidbox: a heated box (air and wall) whose lid is opened now and then (a switched conductance
  read from a held data column), the lamp switched at random.

The measured nodes start at their first (noisy) reading (`initial = data`, as a user writes it),
or with --start fitted at a start fitted per case (`NODE.T0 = y0 range y0 - 2 .. y0 + 2`); the
unmeasured ones at the steady state around them (`initial = data`), the building's envelope at a
fitted start. --verify-truth checks the truth of one case of each family against `thermnet
simulate` at the true params (tolerances 1e-10 relative, 1e-8 K): they agree within 1e-4 K or it
exits 1 (5e-6 K measured when written; solve_ivp BDF at rtol 1e-9 agreed with the truth to 2e-6 K).

Usage: null_cases.py PATH/TO/thermnet [--cases N] [--seed S] [--keep DIR] [--threads T]
                     [--start data|fitted] [--check MAX_RATE] [--verify-truth]
Study mode prints the rate of cases with a false finding and its 95 % Clopper-Pearson interval,
the kinds found per case and the wall time per case, and exits 0. With --check MAX_RATE it exits
1 when the rate exceeds MAX_RATE or when thermnet failed on a case.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
from scipy.linalg import expm
from scipy.stats import beta

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from building_truth import ou  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from timeout_scale import timeout_scale  # noqa: E402

TIMEOUT_S = 600 * timeout_scale()  # scaled for slow builds
UNITS = {"C": "J/K", "G": "W/K", "R": "K/W", "A": "m^2"}


def prbs(rng, n, min_hold, max_hold, first_off=False):
    """0/1 held for a random whole number of samples in [min_hold, max_hold]."""
    u = np.zeros(n)
    k, on = 0, (False if first_off else rng.random() < 0.5)
    while k < n:
        hold = int(rng.integers(min_hold, max_hold + 1))
        u[k:k + hold] = 1.0 if on else 0.0
        k, on = k + hold, not on
    return u


def ar1(rng, n, sd, phi):
    e = np.empty(n)
    e[0] = rng.normal(0, sd)
    w = rng.normal(0, sd * np.sqrt(1 - phi * phi), n)
    for k in range(1, n):
        e[k] = phi * e[k - 1] + w[k]
    return e


# --- the networks -----------------------------------------------------------------------------
# A network: params {name: (kind C|G|R|A, truth)}, nodes [(name, C param)], boundaries
# [(name, column)], links [(element, a, b, param, switch column or None)] (a G param makes a
# `conductance`, an R param a `resistor`), sources [(element, node, aperture param or None,
# column, held)] (a heater of the column's power in W, or aperture * column in W/m^2), measured
# nodes, nodes whose start is fitted, and the data: t, the input columns, the truth's start.

def building(rng):
    dt = float(rng.choice([600.0, 900.0, 1200.0, 1800.0]))
    n = int(rng.integers(300, 700))
    t = np.arange(n) * dt
    hour = t / 3600.0
    swing = rng.uniform(2, 5)
    To = 4.0 + swing * np.sin(2 * np.pi * (hour - 9.0) / 24.0) + ou(rng, n, dt, 12 * 3600, 2.0)
    To = np.round(To, 1)  # a weather station's 0.1 K
    hold = max(1, int(1800 / dt))
    P_on = rng.uniform(1500, 3500)
    Qh = np.round(P_on * prbs(rng, n, hold, 8 * hold), 1)
    day = (hour % 24.0 - 7.0) / 10.0
    peak = rng.uniform(300, 600)
    clear = np.where((day > 0) & (day < 1), peak * np.sin(np.pi * np.clip(day, 0, 1)), 0.0)
    I = np.round(clear * np.clip(0.6 + ou(rng, n, dt, 3600.0, 0.35), 0.1, 1.0), 0)
    p = dict(Ci=("C", 10 ** rng.uniform(5.8, 6.8)), Ce=("C", 10 ** rng.uniform(6.8, 7.6)),
             Ri=("R", 1 / rng.uniform(400, 1500)), Ro=("R", 1 / rng.uniform(100, 300)),
             Aw=("A", rng.uniform(2, 8)), Ae=("A", rng.uniform(1, 6)))
    net = dict(family="building", params=p, nodes=[("Ti", "Ci"), ("Te", "Ce")],
               boundaries=[("outdoors", "To")],
               links=[("inner", "Ti", "Te", "Ri", None), ("outer", "Te", "outdoors", "Ro", None)],
               sources=[("heating", "Ti", None, "Qh", True), ("sun_i", "Ti", "Aw", "I_sol", False),
                        ("sun_e", "Te", "Ae", "I_sol", False)],
               measured=["Ti"], fitted_start=["Te"], t=t,
               cols=dict(To=To, Qh=Qh, I_sol=I))
    # Days of heating before the record: the steady state of the first day's mean inputs.
    first = t < 24 * 3600
    net["x0"] = steady(net, {c: v[first].mean() for c, v in net["cols"].items()})
    return net


def room_series(rng, n, dt):
    """A lab's air: 19-24 degC drifting slowly, read at 0.01 K."""
    return np.round(rng.uniform(19, 24) + ou(rng, n, dt, 3 * 3600, 0.4), 2)


def rig(rng, size):
    dt = float(rng.choice([10.0, 20.0, 30.0, 60.0]))
    n = int(rng.integers(400, 1500))
    t = np.arange(n) * dt
    Tr = room_series(rng, n, dt)
    hold = max(1, int(120 / dt))
    P_on = rng.uniform(5, 40)
    Qh = np.round(P_on * prbs(rng, n, hold, 12 * hold, first_off=True), 2)
    Ch, Cp = 10 ** rng.uniform(2.3, 3.0), 10 ** rng.uniform(3.0, 3.8)
    p = dict(Ch=("C", Ch), Cp=("C", Cp), Ghp=("G", rng.uniform(0.5, 3.0)),
             Gpa=("G", rng.uniform(0.2, 1.5)))
    nodes = [("H", "Ch"), ("P", "Cp")]
    links = [("contact_hp", "H", "P", "Ghp", None), ("loss_p", "P", "room", "Gpa", None)]
    if size == 2:
        p["Rha"] = ("R", 1 / rng.uniform(0.05, 0.3))
        links.append(("loss_h", "H", "room", "Rha", None))
        measured = [["H", "P"], ["P"], ["H"]][int(rng.integers(3))]
    elif size == 3:
        p["Cb"] = ("C", 10 ** rng.uniform(2.8, 3.5))
        p["Gbp"] = ("G", rng.uniform(0.3, 2.0))
        p["Gba"] = ("G", rng.uniform(0.05, 0.4))
        nodes.append(("B", "Cb"))
        links += [("mount", "P", "B", "Gbp", None), ("loss_b", "B", "room", "Gba", None)]
        measured = [["H", "B"], ["P", "B"], ["H", "P", "B"]][int(rng.integers(3))]
    else:
        p["Cb"] = ("C", 10 ** rng.uniform(2.8, 3.5))
        p["Cq"] = ("C", 10 ** rng.uniform(2.8, 3.5))
        p["Gpb"] = ("G", rng.uniform(0.3, 2.0))
        p["Gpq"] = ("G", rng.uniform(0.3, 2.0))
        p["Rbq"] = ("R", 1 / rng.uniform(0.1, 1.0))
        p["Gba"] = ("G", rng.uniform(0.05, 0.4))
        p["Gqa"] = ("G", rng.uniform(0.05, 0.4))
        nodes += [("B", "Cb"), ("Q", "Cq")]
        links += [("arm_b", "P", "B", "Gpb", None), ("arm_q", "P", "Q", "Gpq", None),
                  ("bridge", "B", "Q", "Rbq", None), ("loss_b", "B", "room", "Gba", None),
                  ("loss_q", "Q", "room", "Gqa", None)]
        measured = [["H", "B", "Q"], ["P", "B", "Q"], ["B", "Q"]][int(rng.integers(3))]
    net = dict(family=f"rig{size}", params=p, nodes=nodes, boundaries=[("room", "Tr")],
               links=links, sources=[("heater", "H", None, "Qh", True)], measured=measured,
               fitted_start=[], t=t, cols=dict(Tr=Tr, Qh=Qh))
    net["x0"] = np.full(len(nodes), Tr[0])
    return net


def lidbox(rng):
    dt = float(rng.choice([10.0, 15.0, 30.0]))
    n = int(rng.integers(400, 1500))
    t = np.arange(n) * dt
    Tr = room_series(rng, n, dt)
    hold = max(1, int(60 / dt))
    P_on = rng.uniform(10, 25)
    Qh = np.round(P_on * prbs(rng, n, hold, 20 * hold, first_off=True), 2)
    lid = np.zeros(n)
    k = int(rng.integers(n // 8, n // 4))
    while k < n:
        length = int(rng.uniform(300, 900) / dt)
        lid[k:k + length] = 1.0
        k += length + int(rng.uniform(0.15, 0.35) * n)
    p = dict(Ca=("C", rng.uniform(300, 1200)), Cw=("C", rng.uniform(3000, 12000)),
             Gaw=("G", rng.uniform(1.5, 6.0)), Gwr=("G", rng.uniform(0.3, 2.0)),
             Glid=("G", rng.uniform(1.0, 5.0)))
    measured = [["air"], ["air", "wall"]][int(rng.integers(2))]
    net = dict(family="lidbox", params=p, nodes=[("air", "Ca"), ("wall", "Cw")],
               boundaries=[("room", "Tr")],
               links=[("inner", "air", "wall", "Gaw", None), ("outer", "wall", "room", "Gwr", None),
                      ("lid", "air", "room", "Glid", "lid")],
               sources=[("lamp", "air", None, "Qh", True)], measured=measured, fitted_start=[],
               t=t, cols=dict(Tr=Tr, Qh=Qh, lid=lid))
    net["x0"] = np.full(2, Tr[0])
    return net


FAMILIES = [building, lambda r: rig(r, 2), lambda r: rig(r, 3), lambda r: rig(r, 4), lidbox]


# --- the truth: exact discretisation ----------------------------------------------------------

def conductance(net, par):
    kind, v = net["params"][par]
    return 1.0 / v if kind == "R" else v


def matrices(net, switches):
    """x' = A x + B u, u = the columns in sorted order; switches {column: 0 or 1}."""
    names = [nd for nd, _ in net["nodes"]]
    idx = {nd: i for i, nd in enumerate(names)}
    cols = sorted(net["cols"])
    ci = {c: j for j, c in enumerate(cols)}
    bcol = dict(net["boundaries"])
    N = len(names)
    A, B = np.zeros((N, N)), np.zeros((N, len(cols)))
    for _, a, b, par, sw in net["links"]:
        g = conductance(net, par) * (switches[sw] if sw else 1.0)
        for x, y in ((a, b), (b, a)):
            if x not in idx:
                continue
            A[idx[x], idx[x]] -= g
            if y in idx:
                A[idx[x], idx[y]] += g
            else:
                B[idx[x], ci[bcol[y]]] += g
    for _, nd, ap, col, _ in net["sources"]:
        B[idx[nd], ci[col]] += net["params"][ap][1] if ap else 1.0
    C = np.array([net["params"][c][1] for _, c in net["nodes"]])
    return A / C[:, None], B / C[:, None], cols


def steady(net, u):
    A, B, cols = matrices(net, {c: u.get(c, 0.0) for c in net["cols"]})
    return np.linalg.solve(A, -B @ np.array([u[c] for c in cols]))


def simulate(net):
    """States at the samples, exact for the linear inputs linear and the held ones held between
    samples (as thermnet reads `table(data, ...)` and `table(data, ..., hold)`)."""
    t = net["t"]
    h = t[1] - t[0]
    held = {col for _, _, _, col, hd in net["sources"] if hd}
    held |= {sw for *_, sw in net["links"] if sw}
    swcols = sorted({sw for *_, sw in net["links"] if sw})
    cache = {}
    x = np.array(net["x0"], float)
    X = [x]
    cols = sorted(net["cols"])
    U = np.column_stack([net["cols"][c] for c in cols])
    lin = np.array([c not in held for c in cols], float)
    for k in range(t.size - 1):
        key = tuple(net["cols"][s][k] for s in swcols)
        if key not in cache:
            A, B, _ = matrices(net, dict(zip(swcols, key)))
            n, m = B.shape
            M = np.zeros((n + 2 * m, n + 2 * m))
            M[:n, :n], M[:n, n:n + m], M[n:n + m, n + m:] = A * h, B * h, np.eye(m)
            E = expm(M)
            cache[key] = (E[:n, :n], E[:n, n:n + m], E[:n, n + m:])
        Ad, B0, B1 = cache[key]
        du = (U[k + 1] - U[k]) * lin  # the held inputs do not ramp
        x = Ad @ x + B0 @ U[k] + B1 @ du
        X.append(x)
    return np.array(X)


# --- the model and the data -------------------------------------------------------------------

def model_text(net, rng, start="data"):
    lines = [f"# Null case ({net['family']}): the structure of the data's truth, every R, C, G and",
             "# aperture ranged and started 20-50 % away from the truth.",
             f"model null_{net['family']}"]
    for name, (kind, v) in net["params"].items():
        f = 1 + rng.uniform(0.2, 0.5) * (1 if rng.random() < 0.5 else -1)
        u = UNITS[kind]
        if kind == "A":
            lo, hi = 0.0, v * rng.uniform(3, 6)
        else:
            lo, hi = v / rng.uniform(3, 10), v * rng.uniform(3, 10)
        lines.append(f"param {name} = {v * f:.6g} [{u}] range {lo:.6g} [{u}] .. {hi:.6g} [{u}]")
    for b, col in net["boundaries"]:
        lines.append(f'boundary {b} T = table(data, "{col}")')
    for nd, c in net["nodes"]:
        lines.append(f"node {nd} C = {c}")
    for el, a, b, par, sw in net["links"]:
        kind = net["params"][par][0]
        if sw:
            lines.append(f"switched_conductance {el} {a} {b} G = {par} "
                         f'on = table(data, "{sw}", hold)')
        elif kind == "R":
            lines.append(f"resistor {el} {a} {b} R = {par}")
        else:
            lines.append(f"conductance {el} {a} {b} G = {par}")
    for el, nd, ap, col, hd in net["sources"]:
        if ap:
            lines.append(f'heater {el} {nd} P = {ap} * table(data, "{col}") [W/m^2]')
        else:
            lines.append(f'heater {el} {nd} P = table(data, "{col}"{", hold" if hd else ""})')
    lines += ["", "case record {", f"  duration = {net['t'][-1]:g} [s]", "  initial = data"]
    for nd in net["fitted_start"]:
        lines.append(f"  {nd}.T0 = {net['y0_guess'][nd]:.3g} range -10 .. 45")
    if start == "fitted":  # the measured nodes' starts fitted too, from their first reading
        for nd in net["measured"]:
            y0 = net["y_first"][nd]
            lines.append(f"  {nd}.T0 = {y0:.2f} range {y0 - 2:.2f} .. {y0 + 2:.2f}")
    cmap = "; ".join(f"{nd} = y_{nd}" for nd in net["measured"])
    lines += [f'  data "null.csv" {{ {cmap} }}', "}", ""]
    return "\n".join(lines)


def make_case(rng, d, k, start="data"):
    net = FAMILIES[k % len(FAMILIES)](rng) if k < len(FAMILIES) else \
        FAMILIES[int(rng.integers(len(FAMILIES)))](rng)
    X = simulate(net)
    names = [nd for nd, _ in net["nodes"]]
    sd, phi = rng.uniform(0.02, 0.1), rng.uniform(0.5, 0.9)
    ys = {nd: np.round(X[:, names.index(nd)] + ar1(rng, X.shape[0], sd, phi), 2)
          for nd in net["measured"]}
    # The fitted starts begin at the mean of the measured nodes' first readings (a user's guess).
    net["y_first"] = {nd: float(ys[nd][0]) for nd in net["measured"]}
    net["y0_guess"] = {nd: float(np.mean([ys[m][0] for m in net["measured"]]))
                       for nd in net["fitted_start"]}
    cols = sorted(net["cols"])
    with open(os.path.join(d, "null.csv"), "w") as f:
        f.write(",".join(["time"] + cols + [f"y_{nd}" for nd in net["measured"]]) + "\n")
        for i in range(net["t"].size):
            row = [f"{net['t'][i]:g}"] + [f"{net['cols'][c][i]:.10g}" for c in cols] + \
                  [f"{ys[nd][i]:.2f}" for nd in net["measured"]]
            f.write(",".join(row) + "\n")
    with open(os.path.join(d, "null.tnet"), "w") as f:
        f.write(model_text(net, rng, start))
    desc = dict(family=net["family"], samples=int(net["t"].size), dt=float(net["t"][1]),
                measured=net["measured"], noise_sd=round(sd, 4), noise_phi=round(phi, 3),
                truth={p: v for p, (_, v) in net["params"].items()},
                states_range=[float(X.min()), float(X.max())])
    with open(os.path.join(d, "truth.json"), "w") as f:
        json.dump(desc, f, indent=1)
    return desc


def verify_truth(exe, root, seed):
    """The truth against thermnet's own simulation at the true params, one case per family: the
    data file holds the noise-free states, so that both start from the same state."""
    rng = np.random.default_rng(seed)
    worst = 0.0
    for k, family in enumerate(FAMILIES):
        net = family(rng)
        X = simulate(net)
        names = [nd for nd, _ in net["nodes"]]
        net["y_first"] = {nd: float(X[0, names.index(nd)]) for nd in net["measured"]}
        net["y0_guess"] = {nd: 10.0 for nd in net["fitted_start"]}
        d = os.path.join(root, f"verify{k}")
        os.makedirs(d, exist_ok=True)
        cols = sorted(net["cols"])
        with open(os.path.join(d, "null.csv"), "w") as f:
            f.write(",".join(["time"] + cols + [f"y_{nd}" for nd in net["measured"]]) + "\n")
            for i in range(net["t"].size):
                f.write(",".join([f"{net['t'][i]:g}"] + [f"{net['cols'][c][i]:.10g}" for c in cols]
                                 + [f"{X[i, names.index(nd)]:.8f}" for nd in net["measured"]])
                        + "\n")
        with open(os.path.join(d, "null.tnet"), "w") as f:
            f.write(model_text(net, rng))
        sets = []
        for q, (_, v) in net["params"].items():
            sets += ["--set", f"{q}={v:.12g}"]
        for nd in net["fitted_start"]:
            sets += ["--set", f"{nd}.T0={X[0, names.index(nd)]:.10g}"]
        r = subprocess.run([exe, "simulate", "null.tnet", "-o", "sim.csv", "--output",
                            f"{net['t'][1]:g}", "--rtol", "1e-10", "--atol", "1e-8"] + sets,
                           cwd=d, capture_output=True, text=True)
        if r.returncode != 0:
            print(f"{net['family']}: thermnet simulate failed: {r.stderr}")
            return 1
        S = np.genfromtxt(os.path.join(d, "sim.csv"), delimiter=",", names=True)
        err = max(np.max(np.abs(np.interp(net["t"], S["time"], S[nd]) - X[:, names.index(nd)]))
                  for nd in names)
        worst = max(worst, err)
        print(f"{net['family']:8s} {net['t'].size} samples: largest |thermnet - SciPy| over the "
              f"nodes {err:.2e} K")
    return 0 if worst < 1e-4 else 1


def run_case(exe, d, threads):
    t0 = time.monotonic()
    try:
        r = subprocess.run([exe, "diagnose", "null.tnet", "--threads", str(threads), "--json",
                            "out.json"], cwd=d, capture_output=True, text=True, timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return dict(status="hang", wall=time.monotonic() - t0)
    wall = time.monotonic() - t0
    with open(os.path.join(d, "stdout.txt"), "w") as f:
        f.write(r.stdout)
    with open(os.path.join(d, "stderr.txt"), "w") as f:
        f.write(r.stderr)
    if r.returncode != 0 or not os.path.exists(os.path.join(d, "out.json")):
        return dict(status=f"error rc={r.returncode}", wall=wall, stderr=r.stderr[-2000:])
    rep = json.load(open(os.path.join(d, "out.json")))
    found = []
    for x in rep.get("findings", []):
        found.append(dict(kind=x.get("kind"), nodes=x.get("nodes"), element=x.get("element"),
                          rmse_before=x.get("rmse_before"), rmse_after=x.get("rmse_after"),
                          val_before=x.get("validation_rmse_before"),
                          val_after=x.get("validation_rmse_after"),
                          holdout_z=x.get("holdout_z"), window_gain=x.get("window_gain"),
                          block_gain=x.get("block_gain")))
    base = rep.get("baseline", {}).get("rmse")
    # The refitted params of the `parameter` finding, and the rejected candidate that came closest
    # (largest held-out z): how near the null case came to a false finding.
    params = next((x.get("values", {}) for x in rep.get("findings", [])
                   if x.get("kind") == "parameter"), {})
    rej = [x for x in rep.get("rejected", []) if x.get("kind") != "parameter"]
    near = max(rej, key=lambda x: x.get("holdout_z") or -1e300) if rej else None
    if near:
        near = dict(kind=near.get("kind"), nodes=near.get("nodes"), element=near.get("element"),
                    holdout_z=near.get("holdout_z"), window_gain=near.get("window_gain"),
                    rmse_after=near.get("rmse_after"))
    return dict(status="ok", wall=wall, findings=found, baseline=base, params=params,
                nearest_rejected=near)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("thermnet")
    ap.add_argument("--cases", type=int, default=5)
    ap.add_argument("--seed", type=int, default=50)
    ap.add_argument("--keep", metavar="DIR", help="keep every case's files in DIR/caseNN")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--start", choices=["data", "fitted"], default="data",
                    help="measured nodes start at their first reading (initial = data, the "
                    "default) or at a start fitted per case (NODE.T0 = ... range)")
    ap.add_argument("--verify-truth", action="store_true",
                    help="check the SciPy truth against thermnet simulate at the true params")
    ap.add_argument("--check", type=float, metavar="MAX_RATE",
                    help="exit 1 when the false-finding rate exceeds MAX_RATE or a case fails")
    a = ap.parse_args()
    exe = os.path.abspath(a.thermnet)
    root = a.keep or tempfile.mkdtemp(prefix="thermnet_null_")
    os.makedirs(root, exist_ok=True)
    if a.verify_truth:
        rc = verify_truth(exe, root, a.seed)
        if not a.keep:
            shutil.rmtree(root, ignore_errors=True)
        return rc
    rng = np.random.default_rng(a.seed)
    results = []
    for k in range(a.cases):
        d = os.path.join(root, f"case{k:02d}")
        os.makedirs(d, exist_ok=True)
        desc = make_case(rng, d, k, a.start)
        res = run_case(exe, d, a.threads)
        res.update(case=k, desc=desc)
        results.append(res)
        false = [f for f in res.get("findings", []) if f["kind"] != "parameter"]
        kinds = ", ".join(f"{f['kind']} {f['nodes']}{' ' + f['element'] if f['element'] else ''}"
                          for f in res.get("findings", [])) or "none"
        print(f"case {k:2d} {desc['family']:8s} n={desc['samples']:4d} dt={desc['dt']:g} s "
              f"measured={','.join(desc['measured'])} noise {desc['noise_sd']:.3f} K "
              f"phi {desc['noise_phi']:.2f}: {res['status']}, {res['wall']:.1f} s, "
              f"baseline {res.get('baseline') or float('nan'):.4f} K; findings: {kinds}"
              f"{'  <- FALSE' if false else ''}", flush=True)
        for f in false:
            print(f"      {f['kind']} nodes={f['nodes']} element={f['element']} RMSE "
                  f"{f['rmse_before']} -> {f['rmse_after']} K, held-out {f['val_before']} -> "
                  f"{f['val_after']} K, holdout_z {f['holdout_z']}, window_gain "
                  f"{f['window_gain']}, block_gain {f['block_gain']}", flush=True)
        if res.get("params"):
            err = [abs(np.log(res["params"][q] / v)) for q, v in desc["truth"].items()
                   if q in res["params"] and res["params"][q] > 0 and v > 0]
            final = (res["findings"][-1]["rmse_after"] if res["findings"] else res["baseline"])
            near = res.get("nearest_rejected")
            print(f"      params refitted: largest |ln(fit/truth)| {max(err):.3f}; final RMSE "
                  f"{final:.4f} K (noise sd {desc['noise_sd']:.3f} K); closest rejected: "
                  + (f"{near['kind']} {near['nodes']} holdout_z {near['holdout_z']:.2f} "
                     f"window_gain {near['window_gain']:.4f} K" if near else "none"), flush=True)
        if res["status"] != "ok":
            print("      " + res.get("stderr", "").strip().replace("\n", "\n      "), flush=True)
    with open(os.path.join(root, "results.json"), "w") as f:
        json.dump(results, f, indent=1, default=float)
    ok = [r for r in results if r["status"] == "ok"]
    bad = [r for r in results if r["status"] != "ok"]
    x = sum(1 for r in ok if any(f["kind"] != "parameter" for f in r["findings"]))
    n = len(ok)
    lo = beta.ppf(0.025, x, n - x + 1) if x > 0 else 0.0
    hi = beta.ppf(0.975, x + 1, n - x) if x < n else 1.0
    rate = x / n if n else float("nan")
    walls = [r["wall"] for r in results]
    print(f"\nfalse-finding rate: {x}/{n} = {rate:.3f}, 95 % Clopper-Pearson [{lo:.3f}, {hi:.3f}]"
          f"; failed cases (error or hang): {len(bad)}")
    print(f"wall time per case: median {np.median(walls):.1f} s, min {min(walls):.1f} s, "
          f"max {max(walls):.1f} s, total {sum(walls):.0f} s"
          + (f"; files in {root}" if a.keep else ""))
    if not a.keep:
        shutil.rmtree(root, ignore_errors=True)
    if a.check is not None:
        return 1 if (bad or n == 0 or rate > a.check) else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
