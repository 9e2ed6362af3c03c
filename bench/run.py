#!/usr/bin/python3
"""Runs thermnet, SciPy BDF and ngspice on the same plate networks and compares them.

run.py --sizes 10,100,1000,10000,100000 [--thermnet PATH] [--skip-ngspice-above N]
       [--skip-scipy-above N] [--scipy-reference-above N] [--workdir DIR]

Per size (total node count; rows x cols from bench/plate.py):
  1. generate plate_M.{tnet,cir,json};
  2. reference: SciPy BDF at rtol = atol = 1e-9 (sizes <= --scipy-reference-max), else thermnet at
     rtol = atol = 1e-10 (said so in the table);
  3. each solver from a loose tolerance (SciPy and ngspice: their defaults; thermnet: 1e-4, looser
     than its conservative default 1e-6), tightened step by step until the final temperatures are
     within TOL_K = 0.01 K of the reference ("matched accuracy"); the timing of that run is reported;
  4. peak RSS from /usr/bin/time -v of that run.
Wall times: thermnet "solve" = the `--stats` wall of simulate() (model loading, network build and
CSV writing excluded), "proc" = whole process; SciPy = solve_ivp only (JSON loading and matrix
assembly excluded); ngspice = whole process (ngspice reports no separate solve time).
Ratios: thermnet solve / SciPy solve, and thermnet proc / ngspice proc.
thermnet and SciPy are compared on every node; ngspice on the probe nodes it writes.
"""
import argparse
import csv
import math
import os
import re
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import plate  # noqa: E402
from process_time import timed  # noqa: E402

PY = "/usr/bin/python3"
TOL_K = 0.01
# thermnet's default (1e-6) is conservative; like the others it starts loose and is tightened.
TN_LADDER = [(1e-4, 1e-4), (1e-5, 1e-5), (1e-6, 1e-6), (1e-7, 1e-7), (1e-8, 1e-8), (1e-9, 1e-9)]
SCIPY_LADDER = [(1e-3, 1e-6), (1e-4, 1e-6), (1e-5, 1e-6), (1e-6, 1e-6), (1e-7, 1e-7)]  # solve_ivp defaults first
SPICE_LADDER = [1e-3, 1e-4, 1e-5, 1e-6]                                    # ngspice default first
csv.field_size_limit(1 << 30)


def read_final_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    head, last = rows[0], rows[-1]
    return float(last[0]), {h: float(v) for h, v in zip(head[1:], last[1:])}


class Run:
    def __init__(self, **kw):
        self.__dict__.update(kw)


def run_thermnet(exe, base, rtol, atol, duration):
    out = base + f".tn_{rtol:g}.csv"
    cmd = [exe, "simulate", base + ".tnet", "--output", f"{duration:g}", "-o", out, "--stats",
           "--rtol", f"{rtol:g}", "--atol", f"{atol:g}"]
    rc, so, se, wall, rss, _ = timed(cmd)
    m = re.search(r"([0-9.]+) s wall", se)
    if not m or not os.path.exists(out):
        raise RuntimeError(f"thermnet failed (rc {rc}): {se[-2000:]}")
    t_end, final = read_final_csv(out)
    if abs(t_end - duration) > 1e-6:
        raise RuntimeError(f"thermnet output ends at {t_end}")
    stats = se.strip().splitlines()[-1] if se.strip() else ""
    stats = next((l for l in se.splitlines() if l.startswith("thermnet:")), stats)
    return Run(solve=float(m.group(1)), proc=wall, rss=rss, final=final, rc=rc, stats=stats,
               tol=f"rtol {rtol:g} atol {atol:g}")


def run_scipy(base, rtol=None, atol=None, reference=False):
    out = base + ".scipy_final.txt"
    cmd = [PY, os.path.join(HERE, "scipy_reference.py"), base + ".json", "--out", out]
    cmd += ["--reference"] if reference else ["--rtol", f"{rtol:g}", "--atol", f"{atol:g}"]
    rc, so, se, wall, rss, _ = timed(cmd)
    if rc != 0:
        raise RuntimeError(f"scipy failed: {se[-2000:]}")
    w = float(re.search(r"wall_s ([0-9.eE+-]+)", so).group(1))
    st = re.search(r"stats (.*)", so).group(1)
    with open(out) as f:
        vals = [float(x) for x in f]
    return Run(solve=w, proc=wall, rss=rss, vals=vals, stats=st,
               tol="rtol 1e-9 atol 1e-9" if reference else f"rtol {rtol:g} atol {atol:g}")


def run_spice(net, rows, cols, outdir, tag, reltol, duration):
    base, _ = plate.generate(rows, cols, outdir, tag, reltol)
    out = base + ".spice.out"
    if os.path.exists(out):
        os.remove(out)
    rc, so, se, wall, rss, _ = timed(["ngspice", "-b", base + ".cir"], cwd=outdir)
    if rc != 0 or not os.path.exists(out):
        raise RuntimeError(f"ngspice failed (rc {rc}): {(so + se)[-2000:]}")
    with open(out) as f:
        lines = [l.split() for l in f if l.strip()]
    head = lines[0]
    last = [float(x) for x in lines[-1]]
    if abs(last[0] - duration) > 1e-3:
        raise RuntimeError(f"ngspice output ends at {last[0]}")
    vals = {h[2:-1]: v for h, v in zip(head[1:], last[1:])}  # 'v(n_0_0)' -> n_0_0
    return Run(solve=wall, proc=wall, rss=rss, final=vals, tol=f"reltol {reltol:g}")


def maxdiff(final_by_name, ref_by_name, names=None):
    names = names if names is not None else list(final_by_name)
    return max(abs(final_by_name[n] - ref_by_name[n]) for n in names if n in ref_by_name)


def fmt(x, spec=".3g"):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "–"
    return format(x, spec)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default="10,100,1000,10000,100000")
    ap.add_argument("--thermnet", default="/tmp/benchbuild/cli/thermnet")
    ap.add_argument("--skip-ngspice-above", type=int, default=10000)
    ap.add_argument("--skip-scipy-above", type=int, default=100000)
    ap.add_argument("--scipy-reference-max", type=int, default=10000,
                    help="largest size whose reference is SciPy at rtol 1e-9 (above: thermnet 1e-10)")
    ap.add_argument("--workdir", default="/tmp/thermnet-bench")
    ap.add_argument("--results", default=os.path.join(HERE, "results", "latest.md"))
    a = ap.parse_args()
    sizes = [int(s) for s in a.sizes.split(",")]
    exe = os.path.abspath(a.thermnet)
    os.makedirs(a.workdir, exist_ok=True)
    rows_out, notes, spice_hist = [], [], []
    for M in sizes:
        rows, cols = plate.shape_for_nodes(M)
        base, net = plate.generate(rows, cols, a.workdir, M)
        names = net["nodes"]
        probes = [names[k] for k in net["probes"]]
        dur = plate.PARAMS["DURATION"]
        print(f"== {M} nodes ({rows} x {cols}) ==", flush=True)
        # reference
        if M <= a.scipy_reference_max:
            r = run_scipy(base, reference=True)
            ref = dict(zip(names, r.vals))
            ref_kind = f"SciPy BDF rtol=atol=1e-9 ({r.solve:.2f} s)"
        else:
            r = run_thermnet(exe, base, 1e-10, 1e-10, dur)
            ref = r.final
            ref_kind = f"thermnet rtol=atol=1e-10 ({r.solve:.2f} s)"
        print(f"  reference: {ref_kind}", flush=True)
        if M <= a.scipy_reference_max and M >= 1000:
            # cross-check: thermnet at 1e-10 against the SciPy reference, justifies the large-size reference
            x = run_thermnet(exe, base, 1e-10, 1e-10, dur)
            notes.append(f"N={M}: thermnet rtol=atol=1e-10 vs SciPy 1e-9 reference: max |dT| = "
                         f"{maxdiff(x.final, ref, names):.2e} K")
            print("  " + notes[-1], flush=True)
        # thermnet
        tn = None
        for rt, at in TN_LADDER:
            t = run_thermnet(exe, base, rt, at, dur)
            t.err = maxdiff(t.final, ref, names)
            print(f"  thermnet {t.tol}: solve {t.solve:.4f} s, proc {t.proc:.3f} s, max|dT| {t.err:.2e} K, "
                  f"rss {t.rss:.0f} MiB, rc {t.rc}\n    {t.stats}", flush=True)
            tn = t
            if t.err <= TOL_K:
                break
        if tn.proc < 2.0:  # repeat short runs, keep the best
            for _ in range(2):
                t2 = run_thermnet(exe, base, *[float(x) for x in tn.tol.split()[1::2]], dur)
                tn.solve, tn.proc = min(tn.solve, t2.solve), min(tn.proc, t2.proc)
        if tn.rc != 0:
            notes.append(f"N={M}: thermnet exited with status {tn.rc} after writing complete output")
        # SciPy
        sc = None
        if M <= a.skip_scipy_above:
            for rt, at in SCIPY_LADDER:
                s = run_scipy(base, rt, at)
                s.err = max(abs(v - ref[n]) for n, v in zip(names, s.vals))
                print(f"  scipy {s.tol}: solve {s.solve:.4f} s, max|dT| {s.err:.2e} K, rss {s.rss:.0f} MiB "
                      f"({s.stats})", flush=True)
                sc = s
                if s.err <= TOL_K:
                    break
            if sc.solve < 2.0:
                for _ in range(2):
                    s2 = run_scipy(base, *[float(x) for x in sc.tol.split()[1::2]])
                    sc.solve = min(sc.solve, s2.solve)
        # ngspice
        spc, spice_note = None, ""
        if M <= a.skip_ngspice_above:
            for rl in SPICE_LADDER:
                s = run_spice(net, rows, cols, a.workdir, M, rl, dur)
                s.err = maxdiff(s.final, ref, probes)
                print(f"  ngspice {s.tol}: {s.proc:.3f} s, max|dT| (probes) {s.err:.2e} K, rss {s.rss:.0f} MiB",
                      flush=True)
                spc = s
                if s.err <= TOL_K:
                    break
            spice_hist.append((M, spc.proc))
        elif len(spice_hist) >= 2:
            (m1, t1), (m2, t2) = spice_hist[-2:]
            p = math.log(t2 / t1) / math.log(m2 / m1)
            spice_note = f"skipped (estimated {t2 * (M / m2) ** p:.0f} s, exponent {p:.2f})"
        else:
            spice_note = "skipped"
        rows_out.append(dict(M=M, shape=f"{rows}x{cols}", ref=ref_kind, tn=tn, sc=sc, sp=spc, spn=spice_note))

    # table
    hdr = ("| N | thermnet solve s | thermnet proc s | thermnet tol | SciPy solve s | SciPy tol | ngspice proc s "
           "| ngspice tol | tn/SciPy (solve/solve) | tn/ngspice (proc/proc) | max abs dT K tn / SciPy / ngspice "
           "| peak RSS MiB tn / SciPy / ngspice | reference |")
    lines = [hdr, "|" + "---|" * hdr.count("|")[:-1] if False else "|" + "---|" * (hdr.count("|") - 1)]
    prev = None
    for r in rows_out:
        tn, sc, sp = r["tn"], r["sc"], r["sp"]
        lines.append("| " + " | ".join([
            f"{r['M']} ({r['shape']})", f"{tn.solve:.4g}" if tn.solve > 0 else "<0.0005", f"{tn.proc:.4g}", tn.tol,
            f"{sc.solve:.4g}" if sc else "skipped", sc.tol if sc else "–",
            f"{sp.proc:.4g}" if sp else r["spn"], sp.tol if sp else "–",
            (f"{tn.solve / sc.solve:.3g}" if tn.solve > 0 else f"<{0.0005 / sc.solve:.2g}") if sc else "–",
            f"{tn.proc / sp.proc:.3g}" if sp else "–",
            " / ".join([f"{tn.err:.1e}", f"{sc.err:.1e}" if sc else "–", f"{sp.err:.1e}" if sp else "–"]),
            " / ".join([f"{tn.rss:.0f}", f"{sc.rss:.0f}" if sc else "–", f"{sp.rss:.0f}" if sp else "–"]),
            r["ref"]]) + " |")
    scal = []
    big = [r for r in rows_out if r["tn"].solve >= 0.01]  # --stats prints ms resolution
    for r1, r2 in zip(big, big[1:]):
        p = math.log(max(r2["tn"].solve, 1e-9) / max(r1["tn"].solve, 1e-9)) / math.log(r2["M"] / r1["M"])
        scal.append(f"{r1['M']}→{r2['M']}: {p:.2f}")
    text = "\n".join(lines) + "\n\n"
    text += "thermnet solve-time growth exponent (t ∝ N^p, sizes with solve >= 10 ms): " + ", ".join(scal) + "\n\n"
    text += "thermnet solver stats at the reported tolerance:\n\n" + "\n".join(
        f"- N={r['M']}: `{r['tn'].stats}`" for r in rows_out) + "\n"
    if notes:
        text += "\nNotes:\n\n" + "\n".join(f"- {n}" for n in notes) + "\n"
    print()
    print(text)
    os.makedirs(os.path.dirname(a.results), exist_ok=True)
    with open(a.results, "w") as f:
        f.write(f"# Benchmark results (bench/run.py)\n\nCommand: `{' '.join(sys.argv)}`\n\n"
                f"Generated {time.strftime('%Y-%m-%d %H:%M:%S')}. Matched accuracy: max |dT| <= {TOL_K} K "
                f"vs reference at the final time (thermnet, SciPy: every node; ngspice: probe nodes).\n\n")
        f.write(text)


if __name__ == "__main__":
    main()
