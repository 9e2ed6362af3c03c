"""Network shapes a thermal engineer meets, built at random from a seed: a bar (chain), a plate
(grid), an instrument (a tree of parts on a mount, radiating to space) and an electronics box
(walls, inside air, boards and components, on a cold plate, with a lid).

Each builder returns the nominal Network: ranged params at their nominal values, node capacities,
links, heaters, and the cases (heater schedules, boundary changes, and the lid's events for a box).
Heater powers are scaled so that the hottest node rises about 15-30 K at steady state.
"""
from __future__ import annotations

import numpy as np

from network import (
    SIGMA_SB, ZERO_C, Boundary, Case, Heater, Link, Network, Node, Param, Signal,
    conductance, nominal_params, sig4,
)

DURATION = 10800.0  # s, every case: 3 h (unless the table's row says otherwise)
OUTPUT = 60.0  # s between samples
TIMING = (DURATION, OUTPUT)


def _param(rng, name, nominal, unit, desc, hi_cap=None) -> Param:
    lo = sig4(nominal * rng.uniform(0.5, 0.65))
    hi = sig4(nominal * rng.uniform(1.4, 1.7))
    if hi_cap is not None:
        hi = min(hi, hi_cap)
    return Param(name, sig4(nominal), lo, hi, unit, desc)


def _heater_schedule(rng, duration: float) -> Signal:
    """On at t_on with P1, maybe a second level, off before the end (unit power, scaled later)."""
    t_on = float(rng.choice([0.0, 300.0, 600.0, 1200.0]))
    t_mid = t_on + float(rng.choice([1800.0, 2400.0, 3000.0]))
    t_off = min(t_mid + float(rng.choice([1200.0, 1800.0, 2400.0])), duration - 2400.0)
    p1, p2 = 1.0, float(rng.choice([0.0, 0.4, 0.6, 1.4]))
    pts = [(0.0, 0.0), (t_on, p1), (t_mid, p2), (t_off, 0.0)] if t_on > 0 else [(0.0, p1), (t_mid, p2), (t_off, 0.0)]
    return Signal("step", pts)


def _constant_heater(rng) -> Signal:
    """Electronics that run all the time, or switch on once."""
    if rng.uniform() < 0.5:
        return Signal.const(1.0)
    return Signal("step", [(0.0, 0.0), (float(rng.choice([600.0, 1800.0, 3600.0])), 1.0)])


def _ambient(rng, start: float, swing: float) -> Signal:
    """A boundary that drifts by up to +-swing K during the test (pwl)."""
    t1 = float(rng.choice([1800.0, 3600.0, 5400.0]))
    t2 = t1 + float(rng.choice([1800.0, 3600.0]))
    d = sig4(rng.uniform(-swing, swing))
    return Signal("pwl", [(0.0, start), (t1, start), (t2, sig4(start + d))])


def _stepped(rng, start: float, change: float) -> Signal:
    """A boundary that is switched once to another set point (a cold plate, a mount)."""
    t1 = float(rng.choice([3600.0, 5400.0, 7200.0]))
    return Signal("step", [(0.0, start), (t1, sig4(start + rng.choice([-1, 1]) * change))])


def _events(rng, duration: float) -> list[tuple[str, float, float]]:
    """One or two lid openings of 5-15 min in the middle of the test."""
    out, t = [], float(rng.choice([1800.0, 2400.0, 3000.0]))
    for _ in range(int(rng.integers(1, 3))):
        length = float(rng.choice([300.0, 600.0, 900.0]))
        if t + length > duration - 1800.0:
            break
        out.append(("lid", t, t + length))
        t += length + float(rng.choice([1800.0, 2400.0, 3600.0]))
    return out


def _scale_heaters(net: Network, target_rise: float) -> None:
    """Scales every heater signal so the steady rise (radiation linearised at 20 degC) of the
    hottest node with all heaters at their peak is target_rise."""
    p = nominal_params(net)
    idx = {n.name: i for i, n in enumerate(net.nodes)}
    n = len(net.nodes)
    A = np.zeros((n, n))
    lin = 4.0 * SIGMA_SB * (20.0 + ZERO_C) ** 3
    for lk in net.links:
        g = conductance(lk, p) * (lin if lk.kind == "radiation" else 1.0)
        for x, y in ((lk.a, lk.b), (lk.b, lk.a)):
            if x in idx:
                A[idx[x], idx[x]] += g
                if y in idx:
                    A[idx[x], idx[y]] -= g
    q = np.zeros(n)
    for h in net.heaters:
        peak = max(max(v for _, v in c.heater_P[h.name].points) for c in net.cases)
        q[idx[h.node]] += peak
    rise = np.linalg.solve(A, q).max()
    for c in net.cases:
        for h in net.heaters:
            c.heater_P[h.name] = c.heater_P[h.name].scaled(target_rise / rise)


def _cases(rng, ncases, heaters: dict[str, str], boundaries: dict[str, tuple], initial: float, events: bool,
           timing: tuple[float, float] = TIMING):
    """heaters: name -> 'schedule' | 'constant'; boundaries: name -> ('ambient'|'stepped'|'const', start, size);
    timing: (duration, output interval) of every case, s."""
    duration, output = timing
    cases = []
    for k in range(ncases):
        bT = {}
        for b, (how, start, size) in boundaries.items():
            if how == "ambient":
                bT[b] = _ambient(rng, start, size)
            elif how == "stepped":
                bT[b] = _stepped(rng, start, size)
            else:
                bT[b] = Signal.const(start)
        hP = {}
        for h, how in heaters.items():
            sig = _heater_schedule(rng, duration) if how == "schedule" else _constant_heater(rng)
            hP[h] = sig.scaled(float(rng.uniform(0.6, 1.0)))
        ev = _events(rng, duration) if events else []
        cases.append(Case(f"run{k + 1}", duration, output, initial, bT, hP, ev))
    return cases


def chain(rng, n: int, ncases: int, events: bool, timing=TIMING) -> Network:
    """An aluminium bar in air: a film heater at one end, bolted to a cold sink at the other
    (capacities known, conductances uncertain)."""
    params = [
        _param(rng, "k_bar", rng.uniform(120, 200), "W/(m*K)", "conductivity of the bar"),
        _param(rng, "h_air", rng.uniform(5, 12), "W/(m^2*K)", "convection bar <-> air"),
        _param(rng, "h_sink", rng.uniform(300, 1500), "W/(m^2*K)", "contact bar <-> sink"),
    ]
    nodes, links = [], []
    for i in range(n):  # the segments were weighed: their capacities are known
        seg = sig4(rng.uniform(0.06, 0.1))
        cs = sig4(rng.uniform(6e-4, 1.4e-3))
        nodes.append(Node(f"s{i + 1}", sig4(seg * cs * 2.43e6), f"segment {i + 1}"))
        links.append(Link(f"cv_s{i + 1}", "convection", f"s{i + 1}", "air", {"h": "h_air", "A": sig4(seg * 4 * np.sqrt(cs))}))
        if i > 0:
            links.append(Link(f"k_s{i}_s{i + 1}", "conduction", f"s{i}", f"s{i + 1}", {"k": "k_bar", "L": seg, "A": cs}))
    links.append(Link("ct_sink", "contact", f"s{n}", "sink", {"h": "h_sink", "A": sig4(rng.uniform(4e-4, 1e-3))}))
    heaters = [Heater("film", "s1", "film heater at the free end")]
    if n >= 8:
        heaters.append(Heater("h_mid", f"s{n // 2}", "clamp-on heater"))
    bounds = [Boundary("air", "room air"), Boundary("sink", "cold sink")]
    cases = _cases(rng, ncases, {h.name: "schedule" for h in heaters},
                   {"air": ("ambient", 20.0, 6.0), "sink": ("stepped", 15.0, 8.0)}, 20.0, events, timing)
    net = Network(f"bar{n}", "chain", f"{n}-segment aluminium bar", params, nodes, bounds, links, heaters, cases)
    _scale_heaters(net, rng.uniform(18, 30))
    return net


def _grid(n: int) -> tuple[int, int]:
    rows = max(r for r in range(1, int(np.sqrt(n)) + 1) if n % r == 0)
    return rows, n // rows


def plate(rng, n: int, ncases: int, events: bool, timing=TIMING) -> Network:
    """A plate of rows x cols cells with components on it, bolted to a cold rail along one edge,
    in air (convection) or in a vacuum chamber (radiation to the shroud)."""
    rows, cols = _grid(n)
    vacuum = rng.uniform() < 0.4
    env = "shroud" if vacuum else "air"
    params = [
        _param(rng, "k_plate", rng.uniform(120, 200), "W/(m*K)", "conductivity of the plate"),
        _param(rng, "h_rail", rng.uniform(400, 1500), "W/(m^2*K)", "contact plate <-> rail"),
        _param(rng, "rc_plate", rng.uniform(2.2e6, 2.6e6), "J/(m^3*K)", "volumetric heat capacity of the plate"),
    ]
    if vacuum:
        params.append(_param(rng, "eps_plate", rng.uniform(0.55, 0.7), "", "emissivity of the plate", 0.98))
    else:
        params.append(_param(rng, "h_air", rng.uniform(5, 12), "W/(m^2*K)", "convection plate <-> air"))
    cell, thick = sig4(rng.uniform(0.04, 0.06)), sig4(rng.uniform(0.004, 0.008))
    name = lambda r, c: f"p{r + 1}_{c + 1}"  # noqa: E731
    nodes, links = [], []
    for r in range(rows):
        for c in range(cols):
            vol = sig4(cell * cell * thick * rng.uniform(0.9, 1.1))
            nodes.append(Node(name(r, c), vol, "", "rc_plate"))
            area = sig4(2 * cell * cell)
            if vacuum:
                links.append(Link(f"r_{name(r, c)}", "radiation", name(r, c), env, {"A": area, "eps1": "eps_plate", "eps2": 1.0}))
            else:
                links.append(Link(f"cv_{name(r, c)}", "convection", name(r, c), env, {"h": "h_air", "A": area}))
            for dr, dc in ((0, 1), (1, 0)):
                if r + dr < rows and c + dc < cols:
                    links.append(Link(f"k_{name(r, c)}_{name(r + dr, c + dc)}", "conduction", name(r, c),
                                      name(r + dr, c + dc), {"k": "k_plate", "L": cell, "A": sig4(cell * thick)}))
    for r in range(rows):
        links.append(Link(f"ct_rail_{r + 1}", "contact", name(r, 0), "rail", {"h": "h_rail", "A": sig4(cell * 0.02)}))
    ncomp = int(np.clip(round(n / 12), 2, 5))
    cells = rng.choice(np.arange(rows * cols), size=ncomp, replace=False)
    heaters = []
    for k, idx in enumerate(sorted(cells)):
        r, c = divmod(int(idx), cols)
        c = max(c, 1) if cols > 1 else c
        heaters.append(Heater(f"q_u{k + 1}", name(r, c), f"component u{k + 1}"))
    bounds = [Boundary(env, "vacuum chamber shroud" if vacuum else "room air"), Boundary("rail", "cold rail")]
    env_sig = ("stepped", -20.0, 15.0) if vacuum else ("ambient", 22.0, 6.0)
    cases = _cases(rng, ncases, {h.name: ("schedule" if k % 2 == 0 else "constant") for k, h in enumerate(heaters)},
                   {env: env_sig, "rail": ("stepped", 20.0, 10.0)}, 20.0, events, timing)
    net = Network(f"plate{n}", "plate", f"{rows} x {cols} plate {'in vacuum' if vacuum else 'in air'}",
                  params, nodes, bounds, links, heaters, cases)
    _scale_heaters(net, rng.uniform(15, 25))
    return net


def tree(rng, n: int, ncases: int, events: bool, timing=TIMING) -> Network:
    """An instrument: a base on a temperature-controlled mount, parts bolted or strutted on it and
    on each other, some radiating to space through radiators, the rest under blankets."""
    params = [
        _param(rng, "h_joint", rng.uniform(800, 2500), "W/(m^2*K)", "contact conductance of bolted joints"),
        _param(rng, "k_strut", rng.uniform(5, 20), "W/(m*K)", "conductivity of the struts (titanium, composite)"),
        _param(rng, "eps_rad", rng.uniform(0.7, 0.85), "", "emissivity of the radiators", 0.98),
        _param(rng, "eps_mli", rng.uniform(0.02, 0.05), "", "effective emissivity of the blankets"),
        _param(rng, "rc_al", rng.uniform(2.2e6, 2.6e6), "J/(m^3*K)", "volumetric heat capacity of aluminium"),
    ]
    names = ["base"] + [f"n{i}" for i in range(1, n)]
    parent = {}
    children = {0: 0}
    nodes = [Node("base", sig4(rng.uniform(6e-4, 1.2e-3)), "instrument base plate", "rc_al")]
    links = [Link("ct_mount", "contact", "base", "mount", {"h": "h_joint", "A": sig4(rng.uniform(2e-3, 5e-3))})]
    for i in range(1, n):
        weights = np.array([1.0 / (1 + children[j]) ** 2 for j in range(i)])
        p = int(rng.choice(i, p=weights / weights.sum()))
        parent[i] = p
        children[p] += 1
        children[i] = 0
        if rng.uniform() < 0.6:
            nodes.append(Node(names[i], sig4(10 ** rng.uniform(-4.7, -3.7)), "", "rc_al"))
        else:
            nodes.append(Node(names[i], sig4(10 ** rng.uniform(1.7, 2.9)), ""))
        how = rng.uniform()
        a, b = names[p], names[i]
        if how < 0.5:
            links.append(Link(f"j_{a}_{b}", "contact", a, b, {"h": "h_joint", "A": sig4(rng.uniform(2e-4, 8e-4))}))
        elif how < 0.8:
            links.append(Link(f"st_{a}_{b}", "conduction", a, b,
                              {"k": "k_strut", "L": sig4(rng.uniform(0.05, 0.15)), "A": sig4(rng.uniform(1e-4, 4e-4))}))
        else:
            links.append(Link(f"g_{a}_{b}", "conductance", a, b, {"G": sig4(rng.uniform(0.1, 0.6))}))
    leaves = [i for i in range(1, n) if children[i] == 0]
    nrad = max(1, len(leaves) // 4)
    radiators = set(int(x) for x in rng.choice(leaves, size=nrad, replace=False))
    for i in range(n):
        if i in radiators:
            links.append(Link(f"rad_{names[i]}", "radiation", names[i], "space",
                              {"A": sig4(rng.uniform(0.02, 0.06)), "eps1": "eps_rad", "eps2": 1.0}))
        else:
            links.append(Link(f"mli_{names[i]}", "radiation", names[i], "space",
                              {"A": sig4(rng.uniform(0.01, 0.04)), "eps1": "eps_mli", "eps2": 1.0}))
    nheat = int(np.clip(round(n / 10), 2, 6))
    where = rng.choice(np.arange(1, n), size=nheat, replace=False)
    heaters = [Heater(f"q_{names[i]}", names[i], "electronics" if k % 2 else "heater") for k, i in enumerate(where)]
    bounds = [Boundary("mount", "temperature-controlled mount"), Boundary("space", "cold shroud (space)")]
    cases = _cases(rng, ncases, {h.name: ("constant" if k % 2 else "schedule") for k, h in enumerate(heaters)},
                   {"mount": ("ambient", 20.0, 8.0), "space": ("const", -40.0, 0.0)}, 20.0, events, timing)
    net = Network(f"instrument{n}", "tree", f"{n}-part instrument", params, nodes, bounds, links, heaters, cases)
    _scale_heaters(net, rng.uniform(15, 25))
    return net


def box(rng, n: int, ncases: int, events: bool, timing=TIMING) -> Network:
    """An electronics box on a cold plate: six walls (split in patches), the air inside, boards
    held by wedge locks in the side walls, components on the boards; the top wall is a lid."""
    params = [
        _param(rng, "h_cp", rng.uniform(500, 2000), "W/(m^2*K)", "contact box <-> cold plate"),
        _param(rng, "h_out", rng.uniform(4, 10), "W/(m^2*K)", "convection walls <-> room"),
        _param(rng, "h_in", rng.uniform(2, 6), "W/(m^2*K)", "convection inside the box"),
        _param(rng, "h_wedge", rng.uniform(500, 1500), "W/(m^2*K)", "wedge-lock contact board <-> wall"),
        _param(rng, "eps_in", rng.uniform(0.6, 0.8), "", "emissivity inside the box", 0.98),
    ]
    patches = max(1, int(round(n * 0.3 / 6)))
    faces = ["bottom", "top", "left", "right", "front", "back"]
    rest = n - 6 * patches - 1
    boards = max(1, min(4, rest // 6))
    per_board = max(1, (rest - boards) // (2 * boards))  # board nodes; the remainder are components
    ncomp = rest - boards * per_board
    nodes, links = [], []
    wall = {}
    for f in faces:
        wall[f] = [f"{f}{k + 1}" if patches > 1 else f for k in range(patches)]
        for k, w in enumerate(wall[f]):
            nodes.append(Node(w, sig4(rng.uniform(80, 200) / patches * 2), f"{f} wall" + (" (lid)" if f == "top" else "")))
            if k > 0:
                links.append(Link(f"g_{wall[f][k - 1]}_{w}", "conductance", wall[f][k - 1], w, {"G": sig4(rng.uniform(0.8, 2.0))}))
            area = sig4(rng.uniform(0.02, 0.05) / patches)
            if f == "bottom":
                links.append(Link(f"ct_{w}", "contact", w, "coldplate", {"h": "h_cp", "A": sig4(area * 0.3)}))
            else:
                links.append(Link(f"cv_{w}", "convection", w, "room", {"h": "h_out", "A": area}))
            links.append(Link(f"ci_{w}", "convection", w, "air_in", {"h": "h_in", "A": area}))
    for f in faces[2:]:  # the side walls are screwed to the bottom and carry the lid
        links.append(Link(f"sc_{f}_b", "conductance", wall[f][0], wall["bottom"][-1], {"G": sig4(rng.uniform(0.3, 1.0))}))
        links.append(Link(f"sc_{f}_t", "conductance", wall[f][-1], wall["top"][0], {"G": sig4(rng.uniform(0.2, 0.6))}))
    nodes.append(Node("air_in", sig4(rng.uniform(20, 40)), "air inside the box"))
    board_nodes = []
    for bi in range(boards):
        names = [f"b{bi + 1}_{k + 1}" for k in range(per_board)]
        board_nodes += names
        for k, b in enumerate(names):
            nodes.append(Node(b, sig4(rng.uniform(60, 150) / per_board * 2), f"board {bi + 1}"))
            if k > 0:
                links.append(Link(f"g_{names[k - 1]}_{b}", "conductance", names[k - 1], b, {"G": sig4(rng.uniform(0.3, 0.8))}))
            links.append(Link(f"ci_{b}", "convection", b, "air_in", {"h": "h_in", "A": sig4(0.02 / per_board)}))
            w = wall["left"][min(k, patches - 1)] if bi % 2 == 0 else wall["right"][min(k, patches - 1)]
            links.append(Link(f"r_{b}_{w}", "radiation", b, w, {"A": sig4(0.01 / per_board), "eps1": "eps_in", "eps2": "eps_in"}))
        for end, side in ((names[0], "left"), (names[-1], "right")):
            links.append(Link(f"wl_{end}_{side}", "contact", end, wall[side][bi % patches], {"h": "h_wedge", "A": sig4(rng.uniform(3e-4, 8e-4))}))
    heaters = []
    for ci in range(ncomp):
        c = f"u{ci + 1}"
        b = board_nodes[int(rng.integers(len(board_nodes)))]
        nodes.append(Node(c, sig4(rng.uniform(5, 30)), f"component on {b}"))
        links.append(Link(f"pad_{c}", "conductance", c, b, {"G": sig4(rng.uniform(0.2, 1.0))}))
        links.append(Link(f"ci_{c}", "convection", c, "air_in", {"h": "h_in", "A": sig4(rng.uniform(5e-4, 2e-3))}))
        if ci < 6:
            heaters.append(Heater(f"q_{c}", c, f"dissipation of {c}"))
    bounds = [Boundary("room", "laboratory air"), Boundary("coldplate", "cold plate")]
    cases = _cases(rng, ncases, {h.name: ("schedule" if k % 2 == 0 else "constant") for k, h in enumerate(heaters)},
                   {"room": ("ambient", 22.0, 4.0), "coldplate": ("stepped", 20.0, 10.0)}, 20.0, events, timing)
    net = Network(f"box{n}", "box", f"electronics box, {len(nodes)} nodes", params, nodes, bounds, links, heaters, cases)
    _scale_heaters(net, rng.uniform(20, 30))
    return net


def panel(rng, n: int, ncases: int, events: bool, timing=TIMING) -> Network:
    """A radiator panel of rows x cols cells in a vacuum chamber: every cell radiates to the
    shroud, the panel is bolted to a cold rail along one edge and carries components; only the
    conductivity and the emissivity are uncertain (its capacities and the bolted joints are known)."""
    rows, cols = _grid(n)
    params = [
        _param(rng, "k_plate", rng.uniform(120, 200), "W/(m*K)", "conductivity of the panel"),
        _param(rng, "eps_plate", rng.uniform(0.7, 0.85), "", "emissivity of the panel", 0.98),
    ]
    h_rail, rc = sig4(rng.uniform(400, 1500)), rng.uniform(2.2e6, 2.6e6)
    cell, thick = sig4(rng.uniform(0.04, 0.06)), sig4(rng.uniform(0.002, 0.004))
    name = lambda r, c: f"p{r + 1}_{c + 1}"  # noqa: E731
    nodes, links = [], []
    for r in range(rows):
        for c in range(cols):
            nodes.append(Node(name(r, c), sig4(rc * cell * cell * thick * rng.uniform(0.9, 1.1)), ""))
            links.append(Link(f"r_{name(r, c)}", "radiation", name(r, c), "shroud",
                              {"A": sig4(cell * cell), "eps1": "eps_plate", "eps2": 1.0}))
            for dr, dc in ((0, 1), (1, 0)):
                if r + dr < rows and c + dc < cols:
                    links.append(Link(f"k_{name(r, c)}_{name(r + dr, c + dc)}", "conduction", name(r, c),
                                      name(r + dr, c + dc), {"k": "k_plate", "L": cell, "A": sig4(cell * thick)}))
    for r in range(rows):
        links.append(Link(f"ct_rail_{r + 1}", "contact", name(r, 0), "rail", {"h": h_rail, "A": sig4(cell * 0.02)}))
    ncomp = int(np.clip(round(n / 12), 2, 6))
    cells = rng.choice(np.arange(rows * cols), size=ncomp, replace=False)
    heaters = []
    for k, idx in enumerate(sorted(cells)):
        r, c = divmod(int(idx), cols)
        heaters.append(Heater(f"q_u{k + 1}", name(r, max(c, 1)), f"component u{k + 1}"))
    bounds = [Boundary("shroud", "vacuum chamber shroud"), Boundary("rail", "cold rail")]
    cases = _cases(rng, ncases, {h.name: ("schedule" if k % 2 == 0 else "constant") for k, h in enumerate(heaters)},
                   {"shroud": ("stepped", -20.0, 15.0), "rail": ("stepped", 20.0, 10.0)}, 20.0, events, timing)
    net = Network(f"panel{n}", "panel", f"{rows} x {cols} radiator panel in vacuum", params, nodes, bounds, links,
                  heaters, cases)
    _scale_heaters(net, rng.uniform(15, 25))
    return net


BUILDERS = {"chain": chain, "plate": plate, "tree": tree, "box": box, "panel": panel}


def build(shape: str, n: int, rng, ncases: int, events: bool, timing=TIMING) -> Network:
    net = BUILDERS[shape](rng, n, ncases, events, timing)
    assert len(net.nodes) == n or shape == "box", (shape, n, len(net.nodes))
    return net
