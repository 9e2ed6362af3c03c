#!/usr/bin/python3
"""Independent-solver cross-check of thermnet against ngspice (electrical analogue).

For each model in models/*.tnet the script
  1. runs `thermnet simulate MODEL -o CSV` (tight tolerances) for thermnet's answer;
  2. reads the same .tnet file with a small independent reader (a subset of the language:
     one statement per line, plain SI numbers / simple expressions, degC temperatures, constant
     or step/pwl signals) and generates a SPICE netlist from those parameters:
       temperature [K] <-> voltage, heat flow <-> current, C <-> capacitor (IC = T0),
       G <-> resistor 1/G, boundary <-> voltage source (PWL for signals),
       heater <-> current source (PWL for step signals),
       radiation <-> B source I = sigma*GR*(V(a)^4 - V(b)^4);
  3. runs `ngspice -b` with tight tolerances (.tran UIC) and reads wrdata output;
  4. interpolates both to thermnet's output times and asserts max |dT| < 0.01 K.

Usage: crosscheck.py PATH/TO/thermnet [MODEL.tnet ...]
Prints one line per model; exits 1 if any model fails (with a per-model report).
"""

import math
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

SIGMA = 5.670374419e-8
ZERO_C = 273.15
TOLERANCE_K = 0.01
STEP_RAMP = 1e-6  # s: width of the ramp that stands for a step in a SPICE PWL

HERE = os.path.dirname(os.path.abspath(__file__))


class ModelError(Exception):
    pass


# ----------------------------------------------------------------------------- model reader

def eval_expr(text, consts):
    if "[" in text:
        raise ModelError(f"units in brackets are not supported by the cross-check reader: {text}")
    env = {"pi": math.pi, "sigma": SIGMA, "sqrt": math.sqrt, "exp": math.exp, "log": math.log,
           "log10": math.log10, "abs": abs, "min": min, "max": max, "pow": pow}
    env.update(consts)
    expr = text.replace("^", "**")
    try:
        return float(eval(expr, {"__builtins__": {}}, env))  # noqa: S307 (trusted test files)
    except Exception as e:  # pragma: no cover
        raise ModelError(f"cannot evaluate '{text}': {e}") from e


def parse_value(text, consts):
    """A constant (float) or a signal ('step'|'pwl', [(t, v), ...])."""
    m = re.fullmatch(r"\s*(step|pwl)\s*\((.*)\)\s*", text)
    if not m:
        return eval_expr(text, consts)
    points = []
    for item in m.group(2).split(","):
        t, v = item.split(":")
        points.append((eval_expr(t, consts), eval_expr(v, consts)))
    return (m.group(1), points)


KEY_RE = re.compile(r"(\w+)\s*=\s*((?:step|pwl)\s*\([^)]*\)|[^\s;]+)")


def parse_keys(text, consts):
    return {k: parse_value(v, consts) for k, v in KEY_RE.findall(text)}


def element_conductance(kind, keys):
    """Conductance [W/K] of a linear element kind (the spec's table)."""
    if kind == "conductance":
        return keys["G"]
    if kind == "resistor":
        return 1.0 / keys["R"]
    if kind == "conduction":
        return keys["k"] * keys["A"] / keys["L"]
    if kind == "cylinder_conduction":
        return 2 * math.pi * keys["k"] * keys["L"] / math.log(keys["r_out"] / keys["r_in"])
    if kind in ("contact", "convection"):
        return keys["h"] * keys["A"]
    raise ModelError(f"element kind '{kind}' is not linear or not supported")


def read_model(path):
    """Returns dict(nodes=[...], links=[...], rad=[...], heaters=[...], case={...})."""
    consts = {}
    lines = []
    with open(path, encoding="utf-8") as f:
        for raw in f:
            line = raw.split("#", 1)[0].strip()
            if line:
                lines.append(line)
    # consts/params first (order does not matter in the language)
    for line in lines:
        m = re.match(r"(const|param)\s+(\w+)\s*=\s*(.+?)(\s+range\b.*|\s+\".*)?$", line)
        if m:
            consts[m.group(2)] = None
    pending = True
    while pending:
        pending = False
        for line in lines:
            m = re.match(r"(const|param)\s+(\w+)\s*=\s*(.+?)(\s+range\b.*|\s+\".*)?$", line)
            if m and consts[m.group(2)] is None:
                try:
                    consts[m.group(2)] = eval_expr(m.group(3), {k: v for k, v in consts.items()
                                                                if v is not None})
                except ModelError:
                    pending = True
    net = {"nodes": [], "links": [], "rad": [], "heaters": [], "case": {}}
    in_case = False
    for line in lines:
        if in_case:
            if line.startswith("}"):
                in_case = False
                continue
            net["case"].update(parse_keys(line, consts))
            continue
        words = line.split()
        kw = words[0]
        if kw in ("model", "const", "param"):
            continue
        if kw == "case":
            m = re.match(r"case\s+\w+\s*\{(.*?)(\})?\s*$", line)
            net["case"].update(parse_keys(m.group(1), consts))
            in_case = m.group(2) is None
            continue
        if kw in ("node", "boundary"):
            keys = parse_keys(line, consts)
            net["nodes"].append({"name": words[1], "boundary": kw == "boundary", **keys})
            continue
        if kw in ("series", "parallel"):
            name, a, b = words[1:4]
            inner = line[line.index("{") + 1:line.rindex("}")]
            gs = []
            for part in inner.split(";"):
                pw = part.split()
                gs.append(element_conductance(pw[0], parse_keys(part, consts)))
            g = 1.0 / sum(1.0 / x for x in gs) if kw == "series" else sum(gs)
            net["links"].append((name, a, b, g))
            continue
        if kw == "heater":
            net["heaters"].append((words[1], words[2], parse_keys(line, consts)["P"]))
            continue
        if kw == "radiation":
            keys = parse_keys(line, consts)
            if "GR" in keys:
                gr = keys["GR"]
            else:
                gr = keys.get("F", 1.0) * keys["A"] / (1 / keys["eps1"] + 1 / keys["eps2"] - 1)
            net["rad"].append((words[1], words[2], words[3], gr))
            continue
        name, a, b = words[1:4]
        net["links"].append((name, a, b, element_conductance(kw, parse_keys(line, consts))))
    return net


# ----------------------------------------------------------------------------- netlist

def spice_node(name):
    return "n_" + name


def pwl_points(signal, scale_offset, duration, kind_hint=None):
    """SPICE PWL point list for a step/pwl signal (values shifted by scale_offset)."""
    kind, pts = signal
    out = []
    if kind == "pwl":
        for t, v in pts:
            out.append((t, v + scale_offset))
    else:  # step: v_k holds on [t_k, t_{k+1}); first value before t_0
        for i, (t, v) in enumerate(pts):
            if i > 0:
                out.append((t, pts[i - 1][1] + scale_offset))
                out.append((t + STEP_RAMP, v + scale_offset))
            else:
                out.append((t, v + scale_offset))
    if out[0][0] > 0:
        out.insert(0, (0.0, out[0][1]))
    if out[-1][0] < duration:
        out.append((duration * 1.01 + 1, out[-1][1]))
    return " ".join(f"{t:.12g} {v:.12g}" for t, v in out)


def netlist(net, out_file):
    case = net["case"]
    duration = case["duration"]
    initial = case.get("initial", 20.0)
    lines = ["* thermnet cross-check netlist (generated)"]
    unknowns = []
    for n in net["nodes"]:
        sn = spice_node(n["name"])
        if n["boundary"]:
            T = n["T"]
            if isinstance(T, tuple):
                lines.append(f"V_{n['name']} {sn} 0 PWL({pwl_points(T, ZERO_C, duration)})")
            else:
                lines.append(f"V_{n['name']} {sn} 0 DC {T + ZERO_C:.12g}")
        else:
            unknowns.append(n["name"])
            if n["C"] > 0:
                T0 = n.get("T0", initial) + ZERO_C
                lines.append(f"C_{n['name']} {sn} 0 {n['C']:.12g} IC={T0:.12g}")
    for name, a, b, g in net["links"]:
        lines.append(f"R_{name} {spice_node(a)} {spice_node(b)} {1.0 / g:.15g}")
    for name, a, b, gr in net["rad"]:
        va, vb = f"V({spice_node(a)})", f"V({spice_node(b)})"
        k = SIGMA * gr
        lines.append(f"B_{name} {spice_node(a)} {spice_node(b)} "
                     f"I = {k:.15g}*({va}*{va}*{va}*{va} - {vb}*{vb}*{vb}*{vb})")
    for name, node, P in net["heaters"]:
        # current from ground into the node
        if isinstance(P, tuple):
            lines.append(f"I_{name} 0 {spice_node(node)} PWL({pwl_points(P, 0.0, duration)})")
        else:
            lines.append(f"I_{name} 0 {spice_node(node)} DC {P:.12g}")
    tstep = case.get("output", duration / 1000.0)
    tmax = duration / 5000.0
    lines += [
        ".options reltol=1e-7 abstol=1e-12 vntol=1e-8 chgtol=1e-16 method=gear maxord=2",
        f".tran {tstep:.12g} {duration:.12g} 0 {tmax:.12g} UIC",
        ".control",
        "set wr_singlescale",
        "set wr_vecnames",
        "option numdgt=15",
        "run",
        "wrdata " + out_file + " " + " ".join(f"v({spice_node(u)})" for u in unknowns),
        "quit",
        ".endc",
        ".end",
    ]
    return "\n".join(lines) + "\n", unknowns


# ----------------------------------------------------------------------------- runs

def run_thermnet(exe, model, tmp):
    out = os.path.join(tmp, "thermnet.csv")
    cmd = [exe, "simulate", model, "-o", out, "--rtol", "1e-9", "--atol", "1e-9"]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"thermnet failed ({p.returncode}): {p.stderr.strip()}")
    with open(out, encoding="utf-8") as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(out, delimiter=",", skiprows=1, ndmin=2)
    return header, data


def run_ngspice(net, tmp):
    out = os.path.join(tmp, "spice.txt")
    text, unknowns = netlist(net, out)
    cir = os.path.join(tmp, "net.cir")
    with open(cir, "w", encoding="utf-8") as f:
        f.write(text)
    p = subprocess.run(["ngspice", "-b", cir], capture_output=True, text=True, cwd=tmp)
    if p.returncode != 0 or not os.path.exists(out):
        raise RuntimeError(f"ngspice failed ({p.returncode}):\n{p.stdout[-2000:]}\n"
                           f"{p.stderr[-2000:]}\nnetlist:\n{text}")
    data = np.loadtxt(out, skiprows=1, ndmin=2)
    return unknowns, data


def check_model(exe, model):
    net = read_model(model)
    with tempfile.TemporaryDirectory(prefix="thermnet_ngspice_") as tmp:
        header, tn = run_thermnet(exe, model, tmp)
        unknowns, sp = run_ngspice(net, tmp)
    t = tn[:, 0]
    ts = sp[:, 0]
    # ngspice's .tran UIC output starts at its first step, not at t = 0: capacitive nodes get
    # their initial condition as the t = 0 point; arithmetic nodes are compared from ts[0] on.
    initial = net["case"].get("initial", 20.0)
    by_name = {n["name"]: n for n in net["nodes"]}
    worst, worst_node, worst_t = 0.0, None, None
    for j, name in enumerate(unknowns):
        if name not in header:
            raise RuntimeError(f"thermnet output has no column '{name}'")
        T_tn = tn[:, header.index(name)] + ZERO_C
        tsj, vj, mask = ts, sp[:, 1 + j], np.ones_like(t, dtype=bool)
        if ts[0] > 0:
            if by_name[name]["C"] > 0:
                tsj = np.concatenate(([0.0], ts))
                vj = np.concatenate(([by_name[name].get("T0", initial) + ZERO_C], vj))
            else:
                mask = t >= ts[0]
        T_sp = np.interp(t, tsj, vj)
        d = np.where(mask, np.abs(T_tn - T_sp), 0.0)
        k = int(np.argmax(d))
        if d[k] > worst:
            worst, worst_node, worst_t = float(d[k]), name, float(t[k])
    return worst, worst_node, worst_t, len(unknowns), len(ts)


def main(argv):
    if len(argv) < 2:
        print("usage: crosscheck.py THERMNET [MODEL.tnet ...]", file=sys.stderr)
        return 2
    exe = argv[1]
    models = argv[2:] or sorted(
        os.path.join(HERE, "models", f) for f in os.listdir(os.path.join(HERE, "models"))
        if f.endswith(".tnet"))
    failures = []
    for model in models:
        name = os.path.basename(model)
        try:
            worst, node, at, n, steps = check_model(exe, model)
        except Exception as e:  # report and go on with the next model
            print(f"FAIL {name}: {e}")
            failures.append(name)
            continue
        ok = worst < TOLERANCE_K
        print(f"{'ok  ' if ok else 'FAIL'} {name}: max |T_thermnet - T_ngspice| = {worst:.3e} K "
              f"(node {node} at t = {at:g} s; {n} unknowns, {steps} ngspice points; "
              f"limit {TOLERANCE_K} K)")
        if not ok:
            failures.append(name)
    print(f"{len(models) - len(failures)} passed, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
