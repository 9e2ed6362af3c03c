#!/usr/bin/python3
"""`thermnet import` of SPICE netlists against ngspice on the same netlists.

Each netlist is imported with `thermnet import`, checked with `thermnet lint --werror` and
simulated (tight tolerances); ngspice runs the same netlist (its .tran given a small maximum step,
tight tolerances, the node voltages written with wrdata). Every node's temperature must agree with
the node's voltage to 0.01 K. The Foster networks are also compared with their analytic step
response Zth(t) = sum R_i (1 - exp(-t / (R_i C_i))): the imported Cauer ladder must give it.

Usage: spice_ngspice.py PATH/TO/thermnet
"""

import math
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

TOLERANCE_K = 0.01


def run(cmd, **kw):
    p = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({p.returncode}):\n{p.stdout[-3000:]}\n"
                           f"{p.stderr[-3000:]}")
    return p


def read_csv(path):
    with open(path, encoding="utf-8") as f:
        header = [h.strip('"') for h in f.readline().strip().split(",")]
    return header, np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


def ngspice(tmp, netlist_text, nodes):
    """Runs the netlist in ngspice with tight tolerances; returns times and {node: voltages}."""
    out = os.path.join(tmp, "spice.txt")
    lines = netlist_text.rstrip("\n").split("\n")
    body = []
    tran = None
    for line in lines:
        if line.lower().startswith(".tran"):
            words = line.split()
            tran = words
            stop = float(re.sub(r"[a-zA-Z]+$", "", words[2]) or 0)
            extra = " uic" if "uic" in (w.lower() for w in words) else ""
            body.append(f".tran {words[1]} {words[2]} 0 {stop / 20000:.6g}{extra}")
        elif line.lower().strip() == ".end":
            continue
        else:
            body.append(line)
    assert tran, "the netlist has no .tran"
    body += [
        ".options reltol=1e-7 abstol=1e-12 vntol=1e-9 chgtol=1e-16 method=gear maxord=2",
        ".control", "set wr_singlescale", "set wr_vecnames", "option numdgt=15", "run",
        "wrdata " + out + " " + " ".join(f"v({n})" for n in nodes), "quit", ".endc", ".end"]
    cir = os.path.join(tmp, "driver.cir")
    with open(cir, "w", encoding="utf-8") as f:
        f.write("\n".join(body) + "\n")
    p = subprocess.run(["ngspice", "-b", cir], capture_output=True, text=True, cwd=tmp)
    if p.returncode != 0 or not os.path.exists(out):
        raise RuntimeError(f"ngspice failed ({p.returncode}):\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    data = np.loadtxt(out, skiprows=1, ndmin=2)
    return data[:, 0], {n: data[:, 1 + k] for k, n in enumerate(nodes)}


class Case:
    def __init__(self, exe, tmp, title):
        self.exe, self.tmp, self.title = exe, tmp, title
        self.report = []

    def write(self, name, text):
        path = os.path.join(self.tmp, name)
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
        return path

    def thermnet(self, files):
        model = os.path.join(self.tmp, self.title + ".tnet")
        p = run([self.exe, "import", *files, "-o", model])
        run([self.exe, "lint", "--werror", model])
        out = os.path.join(self.tmp, self.title + ".csv")
        run([self.exe, "simulate", model, "-o", out, "--rtol", "1e-10", "--atol", "1e-10"])
        header, data = read_csv(out)
        return model, p.stderr, header, data

    def compare(self, what, t, got, t_ref, ref):
        # ngspice's output with UIC starts at its first step, not at 0: compare from there on.
        mask = t >= t_ref[0]
        expected = np.interp(t[mask], t_ref, ref)
        d = float(np.max(np.abs(got[mask] - expected)))
        self.report.append(f"{what}: {d:.2e} K")
        if not d < TOLERANCE_K:
            raise AssertionError(f"{self.title}: {what} differs by {d:.4g} K")


def against_ngspice(case, files, text, columns):
    """Imports, simulates and compares every node in `columns` ({thermnet name: SPICE node})."""
    model, log, header, data = case.thermnet(files)
    t_sp, v = ngspice(case.tmp, text, list(columns.values()))
    for name, node in columns.items():
        case.compare(f"{name} vs ngspice", data[:, 0], data[:, header.index(name)], t_sp, v[node])
    return model, log, header, data


LADDER = """* Two boards on a chassis: params, a subcircuit used twice, an include, PWL and DC loads
.include parts.inc
.param r_mount = 2.5 c_board = 150
Vamb amb 0 DC 20          ; the room, 20 degC
Rch chassis amb {r_mount/5}
Cch chassis 0 1.2k
X1 chassis b1 board rs=1.5 cs={c_board}
X2 chassis b2 board rs=2.0
+ cs={c_board * 2}
Iload1 0 b1 PWL(0 5 600 5 601 12 1800 12
+ 1801 0)
Iload2 0 b2 DC 8
Rair b1 b2 10meg
.tran 10 3600
.end
"""

PARTS = """* a circuit board on standoffs: the board's core and its surface
.subckt board mount core rs=1 cs=100
Rso core surf {rs}
Csurf surf 0 {cs/10}
Cc core 0 {cs}
Rst surf mount 0.8
.ends board
"""


def ladder(case):
    parts = case.write("parts.inc", PARTS)
    net = case.write("boards.cir", LADDER)
    assert parts
    model, log, header, data = against_ngspice(
        case, [net], LADDER.replace(".include parts.inc", PARTS),
        {"chassis": "chassis", "b1": "b1", "b2": "b2", "x1.surf": "x1.surf",
         "x2.surf": "x2.surf"})
    # The subcircuit is one submodel, its params (defaults from the .subckt line) used by name,
    # the X cards instances that set them.
    text = open(model, encoding="utf-8").read()
    assert "submodel board(mount, core) {" in text, text
    assert "param rs = 1" in text and "param cs = 100" in text, text
    assert re.search(r"^board x1 chassis b1 rs = 1\.5 cs = 150 ", text, re.M), text
    assert "resistor rso core surf R = rs" in text, text


FOSTER_HELD = """* IGBT junction to case: a datasheet's Foster network, the case held at 60 degC
.param p = 80
Rf1 j n1 0.012
Cf1 j n1 {0.8m/0.012}
Rf2 n1 n2 0.045
Cf2 n1 n2 {12m/0.045}
Rf3 n2 c 0.09
Cf3 n2 c {0.15/0.09}
Vcase c 0 60
Iloss 0 j PWL(0 0 1u {p} 0.2 {p} 0.200001 0 0.6 0)
.tran 0.5m 0.6
.end
"""


def foster_held(case):
    net = case.write("igbt.cir", FOSTER_HELD)
    model, log, header, data = against_ngspice(case, [net], FOSTER_HELD, {"j": "j"})
    assert "Cauer ladder" in log and "cauer_j[1 .. 2]" in log, log
    text = open(model, encoding="utf-8").read()
    assert "n1" not in re.sub(r"#.*", "", text), "the Foster inner nodes must be gone"


FOSTER_STEP = """* A Foster network from a datasheet, its last cell to ground (the heatsink held at 0 K rise)
R1 j a 0.05
C1 j a 0.02
R2 a b 0.2
C2 a b 0.5
R3 b 0 0.6
C3 b 0 5
I1 0 j DC 10
.tran 0.01 20 uic
.end
"""


def foster_step(case):
    net = case.write("step.cir", FOSTER_STEP)
    model, log, header, data = against_ngspice(case, [net], FOSTER_STEP, {"j": "j"})
    cells = [(0.05, 0.02), (0.2, 0.5), (0.6, 5.0)]
    t = data[:, 0]
    zth = sum(R * -np.expm1(-t / (R * C)) for R, C in cells)
    case.compare("j vs 10 W * Zth(t)", t, data[:, header.index("j")], t, 10 * zth)
    assert "cauer_j[1 .. 2]" in log and "with gnd held" in log, log


UIC = """* A wall cooling from its initial conditions
R1 inner outer 0.5
C1 inner 0 2000 IC=40
C2 outer 0 500
R2 outer 0 0.25
.ic V(outer)=30
.tran 5 2000 uic
.end
"""


def uic(case):
    net = case.write("wall.cir", UIC)
    against_ngspice(case, [net], UIC, {"inner": "inner", "outer": "outer"})


CASES = (ladder, foster_held, foster_step, uic)


def main(argv):
    if len(argv) != 2:
        print("usage: spice_ngspice.py THERMNET", file=sys.stderr)
        return 2
    failures = 0
    for fn in CASES:
        with tempfile.TemporaryDirectory(prefix="thermnet_spice_") as tmp:
            case = Case(argv[1], tmp, fn.__name__)
            try:
                fn(case)
                print(f"ok   {fn.__name__}: max |dT| " + "; ".join(case.report))
            except Exception as e:  # report and go on
                failures += 1
                print(f"FAIL {fn.__name__}: {e}")
    print(f"{len(CASES) - failures} passed, {failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
