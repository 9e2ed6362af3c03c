#!/usr/bin/python3
"""`thermnet import` of SPICE netlists against ngspice on the same netlists.

Each netlist is imported with `thermnet import`, checked with `thermnet lint --werror` and
simulated (tight tolerances); ngspice runs the same netlist (its .tran given a small maximum step,
tight tolerances, the node voltages written with wrdata). Every node's temperature must agree with
the node's voltage to 0.01 K. The Foster networks are also compared with their analytic step
response Zth(t) = sum R_i (1 - exp(-t / (R_i C_i))): the imported Cauer ladder must give it.
Subcircuits (used twice, nested, with instance parameters and .param values, node 0 and V, I and
PWL sources inside, a Foster part) must come out as submodels, whose instances' nodes (x1.xa.j)
are named as ngspice names them; a Foster part whose instances differ is flattened, and says so.

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
    assert re.search(r"^board x1 chassis b1 rs = 1\.5 cs = c_board ", text, re.M), text
    # The netlist's .param values it uses are consts, named where used.
    assert "const r_mount = 2.5 " in text and "R = r_mount / 5" in text, text
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


def every_node(header):
    """{thermnet column: SPICE node} for every temperature column but gnd and Cauer ladder nodes
    (ngspice names a subcircuit's nodes as thermnet names an instance's: x1.xa.j)."""
    return {h: h for h in header[1:] if h != "gnd" and "cauer_" not in h}


def no_comments(path):
    return re.sub(r"#.*", "", open(path, encoding="utf-8").read())


NESTED = """* Nested parts: a module of two dies on a spreader, used twice; a cold plate held inside a part
.param tamb = 25 pscale = 2
.subckt die top pd=1 rjc=0.5 cdie=0.02
.param quarter = {half/2} half = {rjc/2}
Rj j mid {half}
Rm mid top {quarter*2}
Cj j 0 {cdie}
Cm mid 0 {cdie/4}
Rg j 0 1k
Ip 0 j {pd*pscale}
.ends die
.subckt module base p1=1 p2=2
Xa spread die pd={p1} rjc=0.4
Xb spread die pd={p2 + 1}
Rs1 spread base 0.2
Cs spread 0 5
Rleak spread 0 50
Iw 0 spread PWL(0 0 100 3 200 0)
.ends module
.subckt plate a tset=15
Vc cp 0 {tset}
Rc a cp 0.1
.ends plate
Vamb amb 0 {tamb}
Rhs hs amb 0.3
Chs hs 0 200
X1 hs module p1=10 p2=15
X2 hs module p1=3
X3 hs plate tset={tamb-5}
.tran 1 600
.end
"""


def nested(case):
    net = case.write("nest.cir", NESTED)
    model = os.path.join(case.tmp, "nested.tnet")
    run([case.exe, "import", net, "-o", model])
    text = no_comments(model)
    # Each subcircuit once, as a submodel; node 0 inside them a terminal gnd; the instance
    # parameters keys (in the parent's params where the X card uses them); the local .param
    # values consts; a V source inside a part a boundary there.
    for line in ("submodel die(top, gnd) {", "param pd = 1", "const half = rjc / 2",
                 "const quarter = half / 2", "resistor rm mid top R = quarter * 2",
                 "resistor rg j gnd R = 1000", "heater ip j P = pd * 2",
                 "submodel module(base, gnd) {", "die xa spread gnd pd = p1 rjc = 0.4",
                 "die xb spread gnd pd = p2 + 1", "resistor rleak spread gnd R = 50",
                 "submodel plate(a) {", "boundary cp T = tset", "module x1 hs gnd p1 = 10 p2 = 15",
                 "module x2 hs gnd p1 = 3", "plate x3 hs tset = tamb - 5", "const tamb = 25",
                 "boundary amb T = tamb"):
        assert line in text, f"{line!r} not in\n{text}"
    assert text.count("submodel ") == 3 and "x1_" not in text, text
    _, _, header, _ = case.thermnet([net])
    columns = every_node(header)
    assert "x2.xb.mid" in columns and "x3.cp" in columns, header
    against_ngspice(case, [net], NESTED, columns)


FOSTER_PART = """* A datasheet's IGBT model (a Foster network) for two switches on one held case
.subckt igbt j c
Rf1 j n1 0.012
Cf1 j n1 {0.8m/0.012}
Rf2 n1 n2 0.045
Cf2 n1 n2 {12m/0.045}
Rf3 n2 c 0.09
Cf3 n2 c {0.15/0.09}
.ends igbt
Vcase c 0 60
X1 j1 c igbt
X2 j2 c igbt
I1 0 j1 PWL(0 0 1u 80 0.2 80 0.200001 0 0.6 0)
I2 0 j2 PWL(0 0 1u 50 0.6 50)
.tran 0.5m 0.6
.end
"""


def foster_part(case):
    net = case.write("igbt2.cir", FOSTER_PART)
    model, log, header, data = against_ngspice(case, [net], FOSTER_PART, {"j1": "j1", "j2": "j2"})
    text = no_comments(model)
    assert "submodel igbt(j, c) {" in text and "node cauer_j[1 .. 2]" not in text, text
    assert "resistor cauer_j_r[1] j cauer_j[1]" in text, text
    assert "x1.cauer_j[1 .. 2]" in log and "Cauer ladder" in log, log
    assert "n1" not in text, "the Foster inner nodes must be gone"
    # The analytic Zth(t) of the second switch's 50 W step (from the steady state at 60 degC).
    cells = [(0.012, 0.8e-3 / 0.012), (0.045, 12e-3 / 0.045), (0.09, 0.15 / 0.09)]
    t = data[:, 0]
    zth = sum(R * -np.expm1(-np.maximum(t - 1e-6, 0) / (R * C)) for R, C in cells)
    case.compare("j2 vs 60 + 50 W * Zth(t)", t[t > 1e-3], data[t > 1e-3, header.index("j2")],
                 t[t > 1e-3], 60 + 50 * zth[t > 1e-3])


FOSTER_SCALED = FOSTER_PART.replace(".subckt igbt j c", ".subckt igbt j c s=1").replace(
    "Rf1 j n1 0.012", "Rf1 j n1 {0.012*s}").replace("X2 j2 c igbt", "X2 j2 c igbt s=2")


def foster_scaled(case):
    net = case.write("igbt3.cir", FOSTER_SCALED)
    model, log, header, data = against_ngspice(case, [net], FOSTER_SCALED,
                                               {"j1": "j1", "j2": "j2"})
    # Two instances whose Foster networks differ give different ladders: the part is flattened,
    # and the import says why.
    text = no_comments(model)
    assert "submodel" not in text and "cauer_j2[1]" in text, text
    assert "subcircuit 'igbt' is written flattened" in log, log


PWL_PART = """* A heated part whose load profile and coolant temperature are its parameters
.subckt part mount p=1 tt=100 tc=15
Ih 0 core PWL(0 0 {tt} {p} {2*tt} {p/2} 400 0)
Vcool cool 0 PWL(0 {tc} 300 {tc+5})
Rcore core mount 0.5
Ccore core 0 40
Rcool core cool 2
.ends part
Vamb amb 0 20
Rm plate amb 0.8
Cp plate 0 300
X1 plate part p=30
X2 plate part p=10 tt=50 tc=25
.tran 1 400
.end
"""


def pwl_part(case):
    net = case.write("pwl.cir", PWL_PART)
    model = os.path.join(case.tmp, "pwl_part.tnet")
    run([case.exe, "import", net, "-o", model])
    text = no_comments(model)
    # PWL points in the part's params: one submodel for both instances.
    assert "heater ih core P = pwl(0: 0, tt: p, 2 * tt: p / 2, 400: 0)" in text, text
    assert "boundary cool T = pwl(0: tc, 300: tc + 5)" in text, text
    assert "part x2 plate p = 10 tt = 50 tc = 25" in text and "x1_" not in text, text
    _, _, header, _ = case.thermnet([net])
    against_ngspice(case, [net], PWL_PART, every_node(header))


CASES = (ladder, foster_held, foster_step, uic, nested, foster_part, foster_scaled, pwl_part)


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
