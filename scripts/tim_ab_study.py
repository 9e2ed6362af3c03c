#!/usr/bin/python3
"""Reproduces the TIM-AB study's numerical experiment with thermnet (docs/inverse.md, tables 1-5).

1. `thermnet simulate models/slab_tim_ab/slab.tnet` at the sampling rates needed; keeps A, B, C, D.
2. `thermnet invert ... --json` for every row of the tables; prints Markdown tables.
Noise (table 4) is SYNTHETIC: uniform in +-0.56 degC on B, C, D (fixed seed), A left exact.
Usage: tim_ab_study.py PATH/TO/thermnet [WORKDIR]
"""
import io, json, os, subprocess, sys, tempfile

import numpy as np

tn = sys.argv[1] if len(sys.argv) > 1 else "thermnet"
work = sys.argv[2] if len(sys.argv) > 2 else tempfile.mkdtemp(prefix="tim_ab_")
os.makedirs(work, exist_ok=True)
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
model = os.path.join(root, "models", "slab_tim_ab", "slab.tnet")
TAU = 467


def data(rate, noise=0.0):
    path = os.path.join(work, f"slab_{rate:g}Hz{'_noisy' if noise else ''}.csv")
    if os.path.exists(path):
        return path
    out = subprocess.run([tn, "simulate", model, "--output", f"{1.0 / rate:g}"], check=True,
                         capture_output=True, text=True).stdout
    header = out[:out.index("\n")].split(",")
    cols = [header.index(n) for n in ["time", "A", "B", "C", "D"]]
    d = np.loadtxt(io.StringIO(out), delimiter=",", skiprows=1, usecols=cols)
    if noise:
        rng = np.random.default_rng(56)
        d[:, 2:] += rng.uniform(-noise, noise, size=d[:, 2:].shape)
    with open(path, "w") as f:
        f.write("time,A,B,C,D\n")
        for r in d:
            f.write(f"{r[0]:.10g}," + ",".join(f"{x:.6f}" for x in r[1:]) + "\n")
    return path


def invert(path, *args):
    rep = os.path.join(work, "rep.json")
    cmd = [tn, "invert", path, "--sensors", "B,C,D", "--true", "A", "--tau", str(TAU),
           "-o", os.path.join(work, "est.csv"), "--json", rep, *args]
    subprocess.run(cmd, check=True, capture_output=True)
    return json.load(open(rep))["metrics"]


def row(label, m):
    window_err = f"{m['window_relative_error']:.2f}" if "window_relative_error" in m else "-"
    row_ms = f"{1e3 * m['row_time_mean']:.3f}" if "row_time_mean" in m else "-"
    return (f"| {label} | {m['mean_relative_error']:.2f} | {window_err} | {m['rmse']:.2f} | "
            f"{m['window_samples']:.0f} | {1e3 * m['window_time_mean']:.3f} | "
            f"{1e3 * m['window_time_max']:.3f} | {row_ms} |")


head = ("| {} | real-time error % | window error % | RMSE K | window samples | ms/window mean "
        "| ms/window max | ms/row mean |\n|---|---|---|---|---|---|---|---|")
print("Table 1: error vs eta (100 Hz, slide 10, no filter)\n" + head.format("eta"))
d100 = data(100)
for eta in [0.2, 0.3, 0.4, 0.6, 0.8, 1, 1.5, 2, 3, 4]:
    print(row(f"{eta:g}", invert(d100, "--eta", str(eta), "--slide", "10")), flush=True)
print("\nTable 2: sampling rate (eta 1, slide 10, no filter)\n" + head.format("rate Hz"))
for rate in [0.5, 1, 2, 5, 10, 100]:
    print(row(f"{rate:g}", invert(data(rate), "--eta", "1", "--slide", "10")), flush=True)
d10 = data(10)
print("\nTable 3: slide step (10 Hz, eta 1, no filter)\n" + head.format("slide"))
for slide in [1, 2, 5, 10, 20]:
    print(row(f"{slide}", invert(d10, "--eta", "1", "--slide", str(slide))), flush=True)
print("\nTable 4: +-0.56 degC noise on B, C, D (10 Hz, eta 4, slide 10; filter window gamma = 0.5)\n"
      + head.format("filter"))
dn = data(10, noise=0.56)
print(row("exact data, no filter", invert(d10, "--eta", "4")), flush=True)
for f in ["none", "savgol", "gaussian", "moving-average"]:
    extra = ["--order", "3"] if f == "savgol" else []
    print(row(f"noisy, {f}", invert(dn, "--eta", "4", "--filter", f, "--gamma", "0.5", *extra)),
          flush=True)
print("\nTable 5: full-time-domain inversion (one fit over the record, 10 Hz)\n" + head.format("data"))
print(row("exact", invert(d10, "--mode", "full")))
for f in ["none", "savgol"]:
    print(row(f"noisy, {f}", invert(dn, "--mode", "full", "--filter", f, "--gamma", "0.05")))
