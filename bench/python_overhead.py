#!/usr/bin/env python3
"""Python call overhead: the 24-node network's 10,000 s transient (bench/models/net24.tnet, rtol =
atol = 1e-6) through thermnet.Model.simulate() against thermnet_bench_small, the same run timed
in-process in C++ (Network build + simulate).

    PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead.py build/bench/thermnet_bench_small [REPS]

The Python time includes what a call does beyond the C++ loop: the param check, the case's
elaboration (instantiate) and the numpy result.
"""

import os
import re
import statistics
import subprocess
import sys
import time

import thermnet

bench_exe = sys.argv[1]
reps = int(sys.argv[2]) if len(sys.argv) > 2 else 300
model_path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "models", "net24.tnet")

m = thermnet.Model.load(model_path)
m.simulate(duration=10000, output=10000)  # warm-up
ms = []
for _ in range(reps):
    t0 = time.perf_counter()
    m.simulate(duration=10000, output=10000, rtol=1e-6, atol=1e-6)
    ms.append((time.perf_counter() - t0) * 1e3)
py_median = statistics.median(ms)

out = subprocess.run([bench_exe, model_path, str(reps), "1e-6"], capture_output=True, text=True,
                     check=True).stdout
cpp_median = float(re.search(r"median ([0-9.]+) ms", out).group(1))
print(f"24-node 10,000 s transient, {reps} runs, median per run:")
print(f"  Python thermnet.Model.simulate: {py_median:.3f} ms")
print(f"  C++ in-process (thermnet_bench_small): {cpp_median:.3f} ms")
print(f"  overhead: {py_median - cpp_median:.3f} ms per call ({py_median / cpp_median:.2f}x)")
