#!/usr/bin/python3
"""Regenerates twin_data.csv: SYNTHETIC measurements of the digital twin (twin.tnet).

The "instrument" is thermnet's own simulation of case `truth` (different initial temperature and
lens/cavity conductances than the design), sampled every 10 s, with Gaussian sensor noise
(sigma 0.1 K, fixed seed) on every node. The lens-centre columns are the truth against which the
hidden-node estimates are scored (they are not given to the filter as measurements).
Usage: make_twin_data.py PATH/TO/thermnet
"""
import csv, io, os, subprocess, sys

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
thermnet = sys.argv[1] if len(sys.argv) > 1 else "thermnet"
out = subprocess.run([thermnet, "simulate", os.path.join(here, "twin.tnet"), "--case", "truth"],
                     check=True, capture_output=True, text=True).stdout
rows = list(csv.DictReader(io.StringIO(out)))
nodes = ["window", "l1_edge", "l1_centre", "l2_edge", "l2_centre", "barrel", "inner", "outer"]
rng = np.random.default_rng(7)
with open(os.path.join(here, "twin_data.csv"), "w", newline="") as f:
    f.write("time," + ",".join(nodes) + "\n")
    for r in rows:
        vals = [float(r[n]) + rng.normal(0.0, 0.1) for n in nodes]
        f.write(f"{float(r['time']):g}," + ",".join(f"{v:.3f}" for v in vals) + "\n")
