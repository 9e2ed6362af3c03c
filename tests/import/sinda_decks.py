"""SINDA/FLUINT decks for the import tests: a network described in Python (in the deck's own
units), written as deck text in the many ways hand-written and Thermal Desktop decks have it
(Fortran numbers, GEN, submodels, INSERT, VARIABLES 0 loads, radiation files), and solved by
SciPy in those same units. The solution never goes through thermnet's conversions: it is the
independent answer thermnet's imported model must reproduce.
"""

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import root

# Ways of writing one number, as Fortran reads them all.
NUMBER_STYLES = ("{:.17g}", "{:.16E}", "{:.16E}D", "+{:.17g}")


def fortran(x, style=0):
    """x written in one of several Fortran forms (1.5, 1.5E+02, 1.5D+02, +1.5)."""
    s = NUMBER_STYLES[style % len(NUMBER_STYLES)]
    if s.endswith("D"):
        return s[:-1].format(x).replace("E", "D")
    if s.startswith("+") and x < 0:
        return "{:.17g}".format(x)
    text = s.format(x)
    if "e" not in text.lower() and "." not in text:
        text += "."  # 150 -> 150. (a real)
    return text


class Deck:
    """A SINDA network in the deck's units: nodes by (submodel, id)."""

    def __init__(self, uid="SI", abszro=-273.15, sigma=None):
        self.uid, self.abszro, self.sigma = uid, abszro, sigma
        self.nodes = {}       # (sub, id) -> {"T": T, "C": C, "boundary": bool}
        self.conductors = []  # (sub, id, (sub, id), (sub, id), G, radiation)
        self.loads = {}       # (sub, id) -> Q (deck units)
        self.timend = None
        self.output = None
        self.steady_first = False

    def node(self, sub, i, T, C, boundary=False):
        self.nodes[(sub, i)] = {"T": T, "C": C, "boundary": boundary}

    def link(self, sub, i, a, b, G, radiation=False):
        self.conductors.append((sub, i, a, b, G, radiation))

    # ------------------------------------------------------------------ physics (deck units)

    def _arrays(self):
        """Index arrays of the network (built once)."""
        if getattr(self, "_keys", None) is None or len(self._keys) != len(self.nodes):
            self._keys = list(self.nodes)
            self._index = {k: i for i, k in enumerate(self._keys)}
            self._ia = np.array([self._index[a] for _, _, a, _, _, _ in self.conductors], dtype=int)
            self._ib = np.array([self._index[b] for _, _, _, b, _, _ in self.conductors], dtype=int)
            self._g = np.array([g for _, _, _, _, g, _ in self.conductors], dtype=float)
            self._rad = np.array([r for _, _, _, _, _, r in self.conductors], dtype=bool)
            self._q = np.array([self.loads.get(k, 0.0) for k in self._keys])
        return self._keys

    def _flows(self, T):
        """Net heat into every node for temperatures T (dict)."""
        keys = self._arrays()
        t = np.array([T[k] for k in keys])
        ta, tb = t[self._ia], t[self._ib]
        z = self.abszro
        sigma = self.sigma if self.sigma is not None else 0.0
        f = np.where(self._rad, sigma * self._g * ((ta - z) ** 4 - (tb - z) ** 4),
                     self._g * (ta - tb))
        q = self._q - np.bincount(self._ia, f, len(keys)) + np.bincount(self._ib, f, len(keys))
        return dict(zip(keys, q))

    def _unknowns(self):
        diffusion = [k for k, n in self.nodes.items() if not n["boundary"] and n["C"] > 0]
        arithmetic = [k for k, n in self.nodes.items() if not n["boundary"] and n["C"] <= 0]
        return diffusion, arithmetic

    def _full(self, diffusion, arithmetic, x_d, x_a):
        T = {k: n["T"] for k, n in self.nodes.items() if n["boundary"]}
        T.update(zip(diffusion, x_d))
        T.update(zip(arithmetic, x_a))
        return T

    def steady(self):
        """Steady temperatures of every node (deck units)."""
        diffusion, arithmetic = self._unknowns()
        free = diffusion + arithmetic
        x0 = np.array([self.nodes[k]["T"] for k in free])

        def residual(x):
            T = self._full(free, [], x, [])
            q = self._flows(T)
            return np.array([q[k] for k in free])

        sol = root(residual, x0, method="hybr", tol=1e-12)
        if np.max(np.abs(residual(sol.x))) > 1e-9:
            raise RuntimeError(f"SciPy steady state failed: {sol.message}")
        return self._full(free, [], sol.x, [])

    def transient(self, times):
        """Temperatures at `times` (deck units) from the node data's T (or the steady state)."""
        diffusion, arithmetic = self._unknowns()
        start = self.steady() if self.steady_first else {k: n["T"] for k, n in self.nodes.items()}
        C = np.array([self.nodes[k]["C"] for k in diffusion])
        guess = np.array([start[k] for k in arithmetic])

        def solve_arithmetic(x_d, guess):
            if not arithmetic:
                return np.array([])

            def residual(x_a):
                q = self._flows(self._full(diffusion, arithmetic, x_d, x_a))
                return np.array([q[k] for k in arithmetic])

            sol = root(residual, guess, method="hybr", tol=1e-12)
            if np.max(np.abs(residual(sol.x))) > 1e-9:
                raise RuntimeError("SciPy: arithmetic nodes did not converge")
            return sol.x

        state = {"guess": guess}

        def rhs(_, x_d):
            x_a = solve_arithmetic(x_d, state["guess"])
            state["guess"] = x_a
            q = self._flows(self._full(diffusion, arithmetic, x_d, x_a))
            return np.array([q[k] for k in diffusion]) / C

        x0 = np.array([start[k] for k in diffusion])
        sol = solve_ivp(rhs, (times[0], times[-1]), x0, method="Radau", t_eval=times,
                        rtol=1e-11, atol=1e-10)
        if not sol.success:
            raise RuntimeError(f"SciPy transient failed: {sol.message}")
        out = []
        for j in range(len(times)):
            x_a = solve_arithmetic(sol.y[:, j], state["guess"])
            out.append(self._full(diffusion, arithmetic, sol.y[:, j], x_a))
        return out

    # ------------------------------------------------------------------ units of thermnet's CSV

    def scale(self):
        """Size of the deck's degree in kelvin."""
        return 1.8 if self.uid == "ENG" else 1.0

    def from_celsius(self, t_c):
        """A thermnet temperature (degC) in the deck's unit."""
        return (np.asarray(t_c) + 273.15) * self.scale() + self.abszro

    def time_unit(self):
        """Seconds per deck time unit."""
        return 3600.0 if self.uid == "ENG" else 1.0

    # ------------------------------------------------------------------ deck text

    def control(self):
        lines = ["HEADER CONTROL DATA, GLOBAL", f"      UID = {self.uid}",
                 f"      ABSZRO = {fortran(self.abszro)}"]
        if self.sigma is not None:
            lines.append(f"      SIGMA = {fortran(self.sigma, 1)}")
        if self.timend is not None:
            lines.append(f"      TIMEND = {fortran(self.timend)}, OUTPUT = {fortran(self.output)}")
        lines.append("      DTIMEI = 0.1, NLOOPS = 100     $ solver settings thermnet ignores")
        return lines

    def node_lines(self, sub):
        """NODE DATA lines of a submodel; runs of equal T and C with consecutive ids as GEN."""
        ids = sorted(i for s, i in self.nodes if s == sub)
        lines, k = [], 0
        while k < len(ids):
            n = self.nodes[(sub, ids[k])]
            j = k + 1
            while (j < len(ids) and ids[j] == ids[j - 1] + 1 and
                   self.nodes[(sub, ids[j])] == n and not n["boundary"]):
                j += 1
            sign = -1 if n["boundary"] else 1
            if j - k >= 3:
                lines.append(f"      GEN {ids[k]}, {j - k}, 1, {fortran(n['T'], k)}, "
                             f"{fortran(n['C'], k + 1)}")
            else:
                for m in range(k, j):
                    lines.append(f"      {sign * ids[m]}, {fortran(n['T'], m)}, "
                                 f"{fortran(n['C'], m + 2)}   $ node {ids[m]}")
            k = j
        return lines

    def conductor_lines(self, sub, radiation):
        lines = []
        for s, i, a, b, G, rad in self.conductors:
            if s != sub or rad != radiation:
                continue
            ref = lambda n: str(n[1]) if n[0] == sub else f"{n[0]}.{n[1]}"
            lines.append(f"      {-i if rad else i}, {ref(a)}, {ref(b)}, {fortran(G, i)}")
        return lines


SUBMODELS = ("BOT_BOX", "TOP_BOX", "PCB_A", "PCB_B", "RADIATOR", "BRACKET", "HARNESS", "LENS")


def thermal_desktop_like(n_nodes=127, n_conductors=2500, seed=52):
    """A deck of the size Thermal Desktop writes for a small instrument: n_nodes diffusion nodes in
    eight submodels (ids not consecutive), a space and a structure boundary, every node radiating
    to space, the other conductors between random pairs (four in five radiative), heat loads on
    every sixth node. SI units, degC, SIGMA as Thermal Desktop writes it."""
    rng = np.random.RandomState(seed)
    d = Deck(uid="SI", abszro=-273.15, sigma=5.6704e-8)
    keys = []
    for k in range(n_nodes):
        sub = SUBMODELS[k % len(SUBMODELS)]
        node_id = 10 * (k // len(SUBMODELS)) + 3 + (k % 3)
        while (sub, node_id) in d.nodes:
            node_id += 1
        d.node(sub, node_id, 20.0, float(rng.uniform(50, 500)))
        keys.append((sub, node_id))
    d.node("SPACE", 1, -270.0, 0.0, boundary=True)
    d.node("STRUCT", 1, 20.0, 0.0, boundary=True)
    count = {s: 0 for s in SUBMODELS}

    def next_id(sub):
        count[sub] += 1
        return count[sub]

    for k in keys:
        d.link(k[0], next_id(k[0]), k, ("SPACE", 1), float(rng.uniform(1e-3, 2e-2)), True)
    for k in keys[::8]:
        d.link(k[0], next_id(k[0]), k, ("STRUCT", 1), float(rng.uniform(0.05, 0.5)))
    pairs = set()
    while len(d.conductors) < n_conductors:
        i, j = sorted(rng.choice(n_nodes, 2, replace=False))
        if (i, j) in pairs:
            continue
        pairs.add((i, j))
        a, b = keys[i], keys[j]
        rad = rng.uniform() < 0.8
        G = float(rng.uniform(1e-4, 5e-3) if rad else rng.uniform(0.01, 0.3))
        d.link(a[0], next_id(a[0]), a, b, G, rad)
    for k in keys[::6]:
        d.loads[k] = float(rng.uniform(0.5, 5.0))
    d.timend, d.output = 7200.0, 60.0
    return d


def td_files(d):
    """The deck's files as Thermal Desktop writes them: the main deck, and the radiation
    conductors in a file of their own. Returns {file name: lines}."""
    subs = sorted({s for s, _ in d.nodes})
    main = ["C Generated like a Thermal Desktop deck", "HEADER OPTIONS DATA",
            "TITLE INSTRUMENT MODEL", "      OUTPUT = instrument.out", *d.control()]
    for s in subs:
        main += [f"HEADER NODE DATA, {s}", *d.node_lines(s)]
    for s in subs:
        lines = d.conductor_lines(s, False)
        if lines:
            main += [f"HEADER CONDUCTOR DATA, {s}", *lines]
    for s in subs:
        loads = sorted((k, q) for k, q in d.loads.items() if k[0] == s)
        if loads:
            main.append(f"HEADER VARIABLES 0, {s}")
            main += [f"      {s}.Q{i} = {s}.Q{i} + {fortran(q, 1)}" for (_, i), q in loads]
    main += ["HEADER OPERATIONS", "      BUILD ALL", "      CALL TRANSIENT"]
    rad = ["C Radiation conductors (RadCAD)"]
    for s in subs:
        lines = d.conductor_lines(s, True)
        if lines:
            rad += [f"HEADER CONDUCTOR DATA, {s}", *lines]
    return {"instrument.sin": main, "instrument_rad.cc": rad}


def hand_written(d):
    """The same network as a person would write it in thermnet: plain names and numbers."""
    names = {k: f"{k[0].lower()}_{k[1]}" for k in d.nodes}
    out = ["model hand"]
    ratio = d.sigma / 5.670374419e-8
    for k, n in d.nodes.items():
        if n["boundary"]:
            out.append(f"boundary {names[k]} T = {n['T']!r}")
        else:
            out.append(f"node {names[k]} C = {n['C']!r} T0 = {n['T']!r}")
    for s, i, a, b, G, rad in d.conductors:
        if rad:
            out.append(f"radiation r_{s.lower()}_{i} {names[a]} {names[b]} GR = {G * ratio!r}")
        else:
            out.append(f"conductance g_{s.lower()}_{i} {names[a]} {names[b]} G = {G!r}")
    for k, q in d.loads.items():
        out.append(f"heater q_{names[k]} {names[k]} P = {q!r}")
    out.append(f"case transient {{ duration = {d.timend!r}; output = {d.output!r} }}")
    return out
