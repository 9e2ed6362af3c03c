#!/usr/bin/python3
"""Regenerates warmup.csv: synthetic measured data for two_plates.tnet.

The "measurements" are thermnet's own simulation of the warmup case, sampled every 60 s, with
Gaussian sensor noise (sigma 0.1 K, fixed seed so the file is reproducible).
Usage: make_warmup_data.py PATH/TO/thermnet
"""
import csv, io, os, subprocess, sys

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
thermnet = sys.argv[1] if len(sys.argv) > 1 else "thermnet"
out = subprocess.run([thermnet, "simulate", os.path.join(here, "two_plates.tnet"), "--output", "60"],
                     check=True, capture_output=True, text=True).stdout
rows = list(csv.DictReader(io.StringIO(out)))
rng = np.random.default_rng(2025)
with open(os.path.join(here, "warmup.csv"), "w", newline="") as f:
    f.write("time,plate1,plate2\n")
    for r in rows:
        noisy = [float(r[n]) + rng.normal(0.0, 0.1) for n in ("plate1", "plate2")]
        f.write(f"{float(r['time']):g},{noisy[0]:.3f},{noisy[1]:.3f}\n")
