#!/usr/bin/python3
"""Generator of the benchmark plate: an R x C grid of nodes (N x N for `plate.py N OUTDIR`).

Every node: capacity C_NODE, conductance G to its right/lower neighbours, radiation GR to a cold
sink; the left edge convects to air; every HEATER_PITCH-th row/column carries a heater, the two
heater groups with different step schedules. The network is written three ways from the one
parameter set below (PARAMS):

  plate_<name>.tnet  thermnet model (case `bench`)
  plate_<name>.cir   ngspice netlist, node voltage = temperature in degC
  plate_<name>.json  arrays for bench/scipy_reference.py (temperatures in degC in the file)

Usage: plate.py N OUTDIR            (N x N, name = N)
       plate.py --nodes M OUTDIR    (rows x cols = M, rows = largest divisor of M <= sqrt(M),
                                     name = M)
ngspice tolerances: --reltol (default 1e-3, ngspice's own default).
"""
import argparse
import json
import math
import os

PARAMS = dict(
    C_NODE=10.0,        # J/K per node
    G=0.5,              # W/K between neighbours
    GR=1e-4,            # m^2 radiative coupling of every node to the sink
    T_SINK=-270.0,      # degC (deep space)
    T_AIR=20.0,         # degC, convective edge
    H=5.0, A_CONV=1e-3, # W/(m^2 K), m^2 per left-edge node
    T0=20.0,            # degC initial
    HEATER_PITCH=4,     # a heater on every 4th row and column
    # step schedules (time s: power W) of the two heater groups
    SCHED_A=[(0.0, 1.0), (900.0, 0.25), (2400.0, 1.5)],
    SCHED_B=[(0.0, 0.0), (600.0, 1.2), (3000.0, 0.0)],
    DURATION=3600.0,
    OUTPUT=60.0,
    SPICE_RAMP=1e-3,    # s: rise time of a heater step in ngspice's PWL sources
)
SIGMA = 5.670374419e-8
KELVIN = 273.15


def shape_for_nodes(m):
    r = int(math.isqrt(m))
    while m % r:
        r -= 1
    return r, m // r


def name(i, j):
    return f"n_{i}_{j}"


def build(rows, cols, p=PARAMS):
    """The network as plain data (the single source for all three writers)."""
    nodes = [name(i, j) for i in range(rows) for j in range(cols)]
    idx = {n: k for k, n in enumerate(nodes)}
    edges = []
    for i in range(rows):
        for j in range(cols):
            if j + 1 < cols:
                edges.append((idx[name(i, j)], idx[name(i, j + 1)]))
            if i + 1 < rows:
                edges.append((idx[name(i, j)], idx[name(i + 1, j)]))
    conv = [idx[name(i, 0)] for i in range(rows)]
    heaters = []  # (node index, group 'A' or 'B')
    hp = p["HEATER_PITCH"]
    for i in range(0, rows, hp):
        for j in range(hp // 2, cols, hp):
            heaters.append((idx[name(i, j)], "A" if ((i // hp) + (j // hp)) % 2 == 0 else "B"))
    if not heaters:
        heaters.append((0, "A"))
    # probes: corners, centre, first heater node, a convective-edge node
    cand = [0, cols - 1, (rows - 1) * cols, rows * cols - 1,
            (rows // 2) * cols + cols // 2, heaters[0][0], conv[len(conv) // 2]]
    probes = []
    for k in cand:
        if k not in probes:
            probes.append(k)
    return dict(rows=rows, cols=cols, nodes=nodes, edges=edges, conv=conv, heaters=heaters,
                probes=probes)


def fmt_sched(s):
    return ", ".join(f"{t:g}: {v:g}" for t, v in s)


def write_tnet(net, path, p=PARAMS):
    nodes = net["nodes"]
    with open(path, "w") as f:
        f.write(f"model plate_{net['rows']}x{net['cols']}\n")
        f.write(f"boundary sink T = {p['T_SINK']:g}\nboundary air T = {p['T_AIR']:g}\n")
        for n in nodes:
            f.write(f"node {n} C = {p['C_NODE']:g} T0 = {p['T0']:g}\n")
        for k, (a, b) in enumerate(net["edges"]):
            f.write(f"conductance g{k} {nodes[a]} {nodes[b]} G = {p['G']:g}\n")
        for n in nodes:
            f.write(f"radiation r_{n} {n} sink GR = {p['GR']:g}\n")
        for a in net["conv"]:
            f.write(f"convection c_{nodes[a]} {nodes[a]} air h = {p['H']:g} A = {p['A_CONV']:g}\n")
        for a, g in net["heaters"]:
            f.write(f"heater h_{nodes[a]} {nodes[a]} P = step({fmt_sched(p['SCHED_' + g])})\n")
        f.write(f"case bench {{\n  duration = {p['DURATION']:g}\n  output = {p['OUTPUT']:g}\n}}\n")


def spice_pwl(sched, ramp, tend):
    pts = [(0.0, sched[0][1])]
    for t, v in sched[1:]:
        pts.append((t, pts[-1][1]))
        pts.append((t + ramp, v))
    pts.append((tend, pts[-1][1]))
    return " ".join(f"{t:.9g} {v:.9g}" for t, v in pts)


def write_cir(net, path, probe_out, reltol=1e-3, p=PARAMS):
    nodes = net["nodes"]
    tsk = p["T_SINK"] + KELVIN
    with open(path, "w") as f:
        f.write(f"* plate {net['rows']}x{net['cols']}: V(node) = temperature in degC, I = W\n")
        f.write(f"Vair air 0 DC {p['T_AIR']:.9g}\n")
        for n in nodes:
            f.write(f"C{n} {n} 0 {p['C_NODE']:.9g} IC={p['T0']:.9g}\n")
        for k, (a, b) in enumerate(net["edges"]):
            f.write(f"Rg{k} {nodes[a]} {nodes[b]} {1.0 / p['G']:.12g}\n")
        for n in nodes:
            f.write(f"Br{n} {n} 0 I = {SIGMA * p['GR']:.12g}*((V({n})+{KELVIN})^4 - {tsk ** 4:.12g})\n")
        for a in net["conv"]:
            f.write(f"Rc{nodes[a]} {nodes[a]} air {1.0 / (p['H'] * p['A_CONV']):.12g}\n")
        for a, g in net["heaters"]:
            f.write(f"Ih{nodes[a]} 0 {nodes[a]} PWL({spice_pwl(p['SCHED_' + g], p['SPICE_RAMP'], p['DURATION'])})\n")
        f.write(f".options reltol={reltol:g} method=gear\n")
        f.write(f".tran {p['OUTPUT']:g} {p['DURATION']:g} uic\n")
        probes = " ".join(f"v({nodes[k]})" for k in net["probes"])
        f.write(".control\nset wr_singlescale\nset wr_vecnames\nrun\n")
        f.write(f"wrdata {probe_out} {probes}\nquit\n.endc\n.end\n")


def write_json(net, path, p=PARAMS):
    n = len(net["nodes"])
    d = dict(
        rows=net["rows"], cols=net["cols"], names=net["nodes"],
        C=[p["C_NODE"]] * n, T0=[p["T0"]] * n,
        edges=[[a, b] for a, b in net["edges"]], G=[p["G"]] * len(net["edges"]),
        GR=[p["GR"]] * n, T_sink=p["T_SINK"], sigma=SIGMA,
        conv_nodes=net["conv"], conv_G=[p["H"] * p["A_CONV"]] * len(net["conv"]), T_air=p["T_AIR"],
        heaters=[dict(node=a, schedule=p["SCHED_" + g]) for a, g in net["heaters"]],
        duration=p["DURATION"], probes=net["probes"],
    )
    with open(path, "w") as f:
        json.dump(d, f)


def generate(rows, cols, outdir, tag, reltol=1e-3):
    os.makedirs(outdir, exist_ok=True)
    net = build(rows, cols)
    base = os.path.join(outdir, f"plate_{tag}")
    write_tnet(net, base + ".tnet")
    write_cir(net, base + ".cir", os.path.abspath(base + ".spice.out"), reltol)
    write_json(net, base + ".json")
    return base, net


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("N", nargs="?", type=int, help="side of the N x N plate")
    ap.add_argument("outdir")
    ap.add_argument("--nodes", type=int, help="total nodes instead of N (rows x cols = nodes)")
    ap.add_argument("--reltol", type=float, default=1e-3, help="ngspice .options reltol")
    a = ap.parse_args()
    if a.nodes:
        rows, cols = shape_for_nodes(a.nodes)
        tag = a.nodes
    else:
        rows = cols = a.N
        tag = a.N
    base, _ = generate(rows, cols, a.outdir, tag, a.reltol)
    print(base)


if __name__ == "__main__":
    main()
