#!/usr/bin/python3
"""Uncertainty bands: thermnet `simulate --samples` against the SciPy loop a user would write.

bands.py --thermnet PATH [--sizes 100,1000] [--samples 200] [--scipy-above N] [--workdir DIR]

The network: a chain of N nodes (100 J/K each) from a 20 degC boundary through N conductances G
to a heater P at its far end, G uniform in 1..3 W/K and P in 5..15 W; 20,000 s, an output every
10 s (2,001 outputs). Per size:
  - thermnet: `simulate chain.tnet --samples S --threads T -o bands.csv` at T = 1 and 2 (its own
    tolerances), the whole process's wall and CPU time (/usr/bin/time);
  - SciPy: S draws of (G, P), each solved by solve_ivp BDF (rtol 1e-6, atol 1e-6, the sparse
    analytic Jacobian), then numpy's percentiles (5, 50, 95) at every output: one process, serial,
    its wall time (skipped above --scipy-above nodes).
The draws differ (each tool its own random numbers), so the two medians of the far node at the
end agree to the sampling error only; the nominal run's far node (G = 2, P = 10) is printed by both
too, and agrees to the tolerances: the same network.
"""
import argparse
import csv
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import process_time  # noqa: E402

PY = "/usr/bin/python3"
DURATION, OUTPUT = 20000.0, 10.0

SCIPY_LOOP = r'''
import sys, time
import numpy as np
from scipy.integrate import solve_ivp
from scipy.sparse import diags
n, samples, seed = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
t0 = time.perf_counter()
rng = np.random.default_rng(seed)
C, T_amb = 100.0, 20.0
t_eval = np.arange(0.0, 20000.0 + 1e-9, 10.0)
runs = np.empty((samples, t_eval.size, n))
def run(G, P):
    main = np.full(n, -2.0 * G / C)
    main[-1] = -G / C                     # the far node: one conductance only
    A = diags([np.full(n - 1, G / C), main, np.full(n - 1, G / C)], [-1, 0, 1], format="csc")
    b = np.zeros(n)
    b[0] = G * T_amb / C
    b[-1] = P / C
    r = solve_ivp(lambda t, T: A @ T + b, (0.0, 20000.0), np.full(n, 20.0), method="BDF",
                  rtol=1e-6, atol=1e-6, jac=A, t_eval=t_eval)
    return r.y.T
for s in range(samples):
    runs[s] = run(rng.uniform(1.0, 3.0), rng.uniform(5.0, 15.0))
bands = np.percentile(runs, [5, 50, 95], axis=0)
print("wall_s", time.perf_counter() - t0)
print("median_far_end", bands[1, -1, -1])
print("nominal_far_end", run(2.0, 10.0)[-1, -1])
'''


def chain_model(n):
    lines = ['param G = 2 [W/K] range 1 .. 3 "link"', 'param P = 10 [W] range 5 .. 15 "heat"',
             "boundary amb T = 20"]
    lines += [f"node n{i} C = 100 [J/K] T0 = 20" for i in range(1, n + 1)]
    lines.append("conductance g0 amb n1 G = G")
    lines += [f"conductance g{i} n{i} n{i + 1} G = G" for i in range(1, n)]
    lines.append(f"heater h n{n} P = P")
    lines.append(f"case run {{ duration = {DURATION:g}; output = {OUTPUT:g} }}")
    return "\n".join(lines) + "\n"


def timed(cmd):
    """(stdout, stderr, wall s, CPU s) of a process that must succeed."""
    t = process_time.timed(cmd)
    if t.rc != 0:
        raise RuntimeError(f"{cmd[0]} failed (rc {t.rc}): {t.stderr[-2000:]}")
    return t.stdout, t.stderr, t.wall_s, t.cpu_s


def far_median(path, n):
    with open(path) as f:
        rows = list(csv.reader(f))
    return float(rows[-1][rows[0].index(f"n{n}_p50")])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--thermnet", required=True)
    ap.add_argument("--sizes", default="100,1000")
    ap.add_argument("--samples", type=int, default=200)
    ap.add_argument("--scipy-above", type=int, default=1000)
    ap.add_argument("--workdir")
    a = ap.parse_args()
    work = a.workdir or tempfile.mkdtemp(prefix="thermnet_bands_")
    os.makedirs(work, exist_ok=True)
    print("| N | samples | thermnet 1 thread: wall s / CPU s | thermnet 2 threads: wall s / CPU s"
          " | SciPy loop wall s (imports excluded) | SciPy / thermnet 1 thread (wall) | far-end median degC "
          "thermnet / SciPy | nominal far end degC thermnet / SciPy |")
    print("|---|---|---|---|---|---|---|---|")
    for n in (int(x) for x in a.sizes.split(",")):
        model = os.path.join(work, f"chain_{n}.tnet")
        with open(model, "w") as f:
            f.write(chain_model(n))
        tn = {}
        for threads in (1, 2):
            out = os.path.join(work, f"bands_{n}_{threads}.csv")
            _, _, wall, cpu = timed([a.thermnet, "simulate", model, "--samples", str(a.samples),
                                     "--threads", str(threads), "-o", out])
            tn[threads] = (wall, cpu, far_median(out, n))
        nominal = os.path.join(work, f"nominal_{n}.csv")
        timed([a.thermnet, "simulate", model, "-o", nominal])
        with open(nominal) as f:
            rows = list(csv.reader(f))
        tn_nominal = float(rows[-1][rows[0].index(f"n{n}")])
        sp_wall, ratio, sp_median, sp_nominal = "skipped", "–", "–", "–"
        if n <= a.scipy_above:
            so, _, _, _ = timed([PY, "-c", SCIPY_LOOP, str(n), str(a.samples), "1"])
            fields = dict(line.split() for line in so.strip().splitlines())
            sp_wall = f"{float(fields['wall_s']):.2f}"
            ratio = f"{float(fields['wall_s']) / tn[1][0]:.1f}"
            sp_median = f"{float(fields['median_far_end']):.2f}"
            sp_nominal = f"{float(fields['nominal_far_end']):.4f}"
        print(f"| {n} | {a.samples} | {tn[1][0]:.2f} / {tn[1][1]:.2f} | {tn[2][0]:.2f} / "
              f"{tn[2][1]:.2f} | {sp_wall} | {ratio} | {tn[1][2]:.2f} / {sp_median} | "
              f"{tn_nominal:.4f} / {sp_nominal} |")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
