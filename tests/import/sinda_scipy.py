#!/usr/bin/python3
"""`thermnet import` of SINDA/FLUINT decks against independent answers.

Each case is a network described in Python in the deck's own units (sinda_decks.py), written as
deck files, imported with `thermnet import`, checked with `thermnet lint --werror`, and simulated
(steady and transient, tight tolerances). The reference is SciPy's solution of the same network
in the deck's units (root for the steady state, Radau for the transient), and where one exists an
analytic solution: the linear profile of a conduction chain, the radiating plate's
T = (Q / (SIGMA G) + T_space^4)^(1/4). Temperatures must agree to 0.01 K.

Usage: sinda_scipy.py PATH/TO/thermnet
"""

import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sinda_decks import Deck, fortran, td_files, thermal_desktop_like  # noqa: E402

TOLERANCE_K = 0.01


def run(cmd, **kw):
    p = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({p.returncode}):\n{p.stdout[-3000:]}\n"
                           f"{p.stderr[-3000:]}")
    return p


def read_csv(path):
    with open(path, encoding="utf-8") as f:
        header = f.readline().strip().split(",")
    header = [h.strip('"') for h in header]
    return header, np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


def name(key):
    return f"{key[0]}[{key[1]}]"


class Case:
    def __init__(self, exe, tmp, title):
        self.exe, self.tmp, self.title = exe, tmp, title
        self.worst = 0.0
        self.report = []

    def write(self, file, lines):
        path = os.path.join(self.tmp, file)
        with open(path, "w", encoding="utf-8") as f:
            f.write("\n".join(lines) + "\n")
        return path

    def import_model(self, files, extra=()):
        model = os.path.join(self.tmp, self.title + ".tnet")
        run([self.exe, "import", *files, "-o", model, *extra])
        run([self.exe, "lint", "--werror", model])
        return model

    def compare(self, what, deck, thermnet_c, expected, tol_k=TOLERANCE_K):
        got = deck.from_celsius(thermnet_c)
        d = np.max(np.abs(got - np.asarray(expected))) / deck.scale()
        self.worst = max(self.worst, d)
        self.report.append(f"{what}: max |dT| = {d:.2e} K")
        if not d < tol_k:
            raise AssertionError(f"{self.title}: {what} differs by {d:.4g} K (limit {tol_k} K)")

    def check_steady(self, deck, model, analytic=None):
        out = os.path.join(self.tmp, self.title + "_steady.csv")
        run([self.exe, "simulate", model, "--steady", "-o", out, "--rtol", "1e-10", "--atol",
             "1e-10"])
        header, data = read_csv(out)
        ref = deck.steady()
        keys = [k for k in deck.nodes if not deck.nodes[k]["boundary"]]
        got = np.array([data[0, header.index(name(k))] for k in keys])
        self.compare("steady vs SciPy", deck, got, [ref[k] for k in keys])
        if analytic:
            self.compare("steady vs analytic", deck, got, [analytic[k] for k in keys])

    def check_transient(self, deck, model):
        out = os.path.join(self.tmp, self.title + "_transient.csv")
        run([self.exe, "simulate", model, "-o", out, "--rtol", "1e-10", "--atol", "1e-10"])
        header, data = read_csv(out)
        times = data[:, 0] / deck.time_unit()
        ref = deck.transient(times)
        keys = [k for k in deck.nodes if not deck.nodes[k]["boundary"]]
        for k in keys:
            self.compare(f"transient {name(k)} vs SciPy", deck, data[:, header.index(name(k))],
                         [r[k] for r in ref])
        self.report = [r for r in self.report if not r.startswith("transient ")]
        self.report.append(f"transient vs SciPy ({len(times)} rows, {len(keys)} nodes): "
                           f"max |dT| = {self.worst:.2e} K")


def chain(case):
    """A conduction chain between two boundaries (GEN nodes and conductors): linear steady
    profile; transient from 20 degC against SciPy."""
    d = Deck(uid="SI", abszro=-273.15)
    d.node("ROD", 1, 100.0, 0, boundary=True)
    for i in range(2, 12):
        d.node("ROD", i, 20.0, 50.0)
    d.node("ROD", 12, 0.0, 0, boundary=True)
    for i in range(1, 12):
        d.link("ROD", i, ("ROD", i), ("ROD", i + 1), 0.7)
    d.timend, d.output = 2000.0, 20.0
    deck = case.write("rod.sin", [
        "C A rod in 12 nodes, two ends held",
        "HEADER OPTIONS DATA",
        "TITLE CONDUCTION CHAIN",
        *d.control(),
        "HEADER NODE DATA, ROD",
        "     -1, 100.0, 0.0",
        "      GEN 2, 10, 1, 20.0, 5.0D1        $ ten diffusion nodes",
        "     -12, 0., 0.",
        "HEADER CONDUCTOR DATA, ROD",
        "      GEN 1, 11, 1, 1, 1, 2, 1, 7.0E-1",
        "HEADER OPERATIONS",
        "      BUILD ALL",
        "      CALL TRANSIENT",
    ])
    model = case.import_model([deck])
    analytic = {("ROD", i): 100.0 * (12 - i) / 11 for i in range(2, 12)}
    case.check_steady(d, model, analytic)
    case.check_transient(d, model)
    text = open(model, encoding="utf-8").read()
    assert "for i in 1 .. 11 { conductance ROD_G[i] ROD[i] ROD[i + 1] G = 0.7 }" in text, text
    assert "node ROD[2 .. 11] C = 50 T0 = 20" in text, text


def plate(case):
    """A plate heated by 50 W radiating to 3 K space (SIGMA as Thermal Desktop writes it, deck in
    kelvin): analytic steady T = (Q / (SIGMA G) + 3^4)^(1/4); the cool-down against SciPy."""
    sigma = 5.6704e-8
    d = Deck(uid="SI", abszro=0.0, sigma=sigma)
    d.node("PLATE", 1, 293.15, 900.0)
    d.node("SPACE", 1, 3.0, 0.0, boundary=True)
    d.link("PLATE", 1, ("PLATE", 1), ("SPACE", 1), 0.85 * 0.5, radiation=True)
    d.loads[("PLATE", 1)] = 50.0
    d.timend, d.output = 36000.0, 360.0
    rad = case.write("plate_rad.cc", [
        "C radiation conductors, as RadCAD writes them beside the deck",
        "HEADER CONDUCTOR DATA, PLATE",
        *d.conductor_lines("PLATE", True),
    ])
    deck = case.write("plate.sin", [
        *d.control(),
        "HEADER NODE DATA, PLATE",
        *d.node_lines("PLATE"),
        "HEADER NODE DATA, SPACE",
        *d.node_lines("SPACE"),
        "HEADER VARIABLES 0, PLATE",
        "      PLATE.Q1 = PLATE.Q1 + 50.0",
        "HEADER OPERATIONS",
        "      CALL FWDBCK",
        "      CALL TPRINT('ALL')",
    ])
    model = case.import_model([deck, rad])
    G = 0.85 * 0.5
    analytic = {("PLATE", 1): (50.0 / (sigma * G) + 3.0 ** 4) ** 0.25}
    case.check_steady(d, model, analytic)
    case.check_transient(d, model)


def eng(case):
    """UID = ENG (BTU, hour, degF, ft^2) with ABSZRO = -460: two submodels, an arithmetic node,
    radiation conductors in an INSERTed file, VARIABLES 0 and SOURCE DATA loads on one node."""
    d = Deck(uid="ENG", abszro=-460.0, sigma=0.1714e-8)
    d.node("BOX", 1, 70.0, 2.5)
    d.node("BOX", 2, 70.0, 1.2)
    d.node("BOX", 3, 70.0, -1.0)       # arithmetic
    d.node("BOX", 4, 70.0, 0.8)
    d.node("PANEL", 10, 40.0, 4.0)
    d.node("PANEL", 11, 40.0, 4.0)
    d.node("ENV", 99, -400.0, 0.0, boundary=True)
    d.node("ENV", 1, 65.0, 0.0, boundary=True)
    d.link("BOX", 1, ("BOX", 1), ("BOX", 2), 0.9)
    d.link("BOX", 2, ("BOX", 2), ("BOX", 3), 0.6)
    d.link("BOX", 3, ("BOX", 3), ("BOX", 4), 0.6)
    d.link("BOX", 4, ("BOX", 4), ("PANEL", 10), 0.3)
    d.link("PANEL", 5, ("PANEL", 10), ("PANEL", 11), 1.1)
    d.link("PANEL", 6, ("PANEL", 11), ("ENV", 1), 0.05)
    d.link("BOX", 100, ("BOX", 1), ("PANEL", 10), 0.35, radiation=True)
    d.link("PANEL", 101, ("PANEL", 10), ("ENV", 99), 1.6, radiation=True)
    d.link("PANEL", 102, ("PANEL", 11), ("ENV", 99), 1.6, radiation=True)
    d.loads[("BOX", 1)] = 17.0 + 8.5
    d.loads[("BOX", 2)] = 10.0
    d.timend, d.output = 12.0, 0.1
    case.write("box_rad.cc", [
        "HEADER CONDUCTOR DATA, BOX",
        *d.conductor_lines("BOX", True),
        "HEADER CONDUCTOR DATA, PANEL",
        *d.conductor_lines("PANEL", True),
    ])
    deck = case.write("box.sin", [
        "C ENG units: BTU, hr, degF",
        *d.control(),
        "HEADER NODE DATA, BOX",
        *d.node_lines("BOX"),
        "HEADER NODE DATA, PANEL",
        *d.node_lines("PANEL"),
        "HEADER NODE DATA, ENV",
        *d.node_lines("ENV"),
        "HEADER CONDUCTOR DATA, BOX",
        *d.conductor_lines("BOX", False),
        "HEADER CONDUCTOR DATA, PANEL",
        *d.conductor_lines("PANEL", False),
        "INSERT box_rad.cc",
        "HEADER SOURCE DATA, BOX",
        "      1, 17.0",
        "HEADER VARIABLES 0, BOX",
        "      BOX.Q1 = BOX.Q1 + 8.5",
        "      Q2 = Q2 + 1.0D1",
        "HEADER OPERATIONS",
        "      BUILD CONFIG, BOX, PANEL, ENV",
        "      CALL TRANSIENT",
        "HEADER OUTPUT CALLS, BOX",
        "      CALL TPRINT('BOX')",
    ])
    model = case.import_model([deck])
    case.check_steady(d, model)
    case.check_transient(d, model)


def big(case):
    """A Thermal Desktop-sized deck: 127 nodes in eight submodels, 2,500 conductors (four in five
    radiative, in a file of their own), VARIABLES 0 loads: steady and transient against SciPy."""
    d = thermal_desktop_like()
    files = [case.write(name, lines) for name, lines in td_files(d).items()]
    model = case.import_model(files)
    case.check_steady(d, model)
    case.check_transient(d, model)
    text = open(model, encoding="utf-8").read()
    assert text.count("\nradiation ") == sum(1 for c in d.conductors if c[5]), "one radiation per conductor"


CASES = (chain, plate, eng, big)


def main(argv):
    if len(argv) != 2:
        print("usage: sinda_scipy.py THERMNET", file=sys.stderr)
        return 2
    exe = argv[1]
    failures = 0
    for fn in CASES:
        with tempfile.TemporaryDirectory(prefix="thermnet_sinda_") as tmp:
            case = Case(exe, tmp, fn.__name__)
            try:
                fn(case)
                print(f"ok   {fn.__name__}: " + "; ".join(case.report))
            except Exception as e:  # report and go on
                failures += 1
                print(f"FAIL {fn.__name__}: {e}")
    print(f"{len(CASES) - failures} passed, {failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
