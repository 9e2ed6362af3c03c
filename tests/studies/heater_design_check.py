#!/usr/bin/python3
"""Study B (docs/heater_design.md) as a test: the model's cold-case heat leak matches the study,
the unheated optics cool to about 15 degC by 3000 s, and the thermostats hold the optics near
their band with small gradients during the flight.

  heater_design_check.py THERMNET
"""
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
MODEL = os.path.join(HERE, "..", "..", "models", "heater_design")
sys.path.insert(0, MODEL)
import analyse  # noqa: E402  (leaks(): the paths to the air summed per part)

ZONES = [f"zone{i}" for i in range(1, 7)]
LENS = ["lens1_c", "lens1_e", "lens2_c", "lens2_e", "lens3_c", "lens3_e"]
T_CLIMB = 2750.0
failures = []


def check(what, ok, detail):
    print(f"{'ok  ' if ok else 'FAIL'} {what}: {detail}")
    if not ok:
        failures.append(what)


def simulate(out_dir, model, *args):
    csv = os.path.join(out_dir, f"{model}{'_'.join(args)}.csv".replace("-", ""))
    subprocess.run([sys.argv[1], "simulate", os.path.join(MODEL, model), *args, "-o", csv], check=True)
    return np.genfromtxt(csv, delimiter=",", names=True)


with tempfile.TemporaryDirectory() as tmp:
    # The heat each path to the air carries with every part at 20 degC: `--flows` at t = 0.
    flows = os.path.join(tmp, "leak_flows.csv")
    subprocess.run([sys.argv[1], "simulate", os.path.join(MODEL, "leak.tnet"), "--flows", flows, "-o",
                    os.path.join(tmp, "leak.csv")], check=True)
    q = analyse.leaks(flows)
    lens = sum(q[z] for z in ZONES)
    window = q["window"] + q["wseat"]
    check("every lens zone and the window assembly have a path to the air",
          set(q) == set(ZONES) | {"window", "wseat"}, ", ".join(sorted(q)))
    split = max(abs(q[z] - p) for _, z, p in analyse.HEATERS)
    check("each zone leaks about what the study's heater split gives it", split < 0.25,
          f"largest difference {split:.2f} W")
    check("lens heat leak at -35 degC (study 17.5 W)", abs(lens - 17.5) < 0.3, f"{lens:.2f} W")
    check("window heat loss at -35 degC (study 16.7 W)", abs(window - 16.7) < 0.3, f"{window:.2f} W")

    cold = simulate(tmp, "heaters.tnet", "--case", "unheated")
    i = int(np.argmin(abs(cold["time"] - 3000.0)))
    mean = np.mean([cold[n][i] for n in LENS])
    check("unheated lenses at 3000 s (study: about 15 degC)", 14.0 < mean < 16.5, f"mean {mean:.2f} degC")

    warm = simulate(tmp, "heaters.tnet", "--case", "thermostats")
    late = warm["time"] >= T_CLIMB
    optics = np.vstack([warm[n][late] for n in LENS + ZONES])
    lo, hi = optics.min(), optics.max()
    check("thermostat-held optics during the flight (study 17.5-20.5 degC)", 16.5 < lo and hi < 21.0,
          f"{lo:.2f} .. {hi:.2f} degC")
    grad = np.max(optics.max(0) - optics.min(0))
    check("largest optics gradient during the flight (study: small, < 2-3 K)", grad < 2.5, f"{grad:.2f} K")

    # The study's requirements (`require` in heaters.tnet): the declared powers have no margin on
    # the lens zones; the powers chosen by `thermnet design` (designed.tnet) meet every one.
    declared = subprocess.run([sys.argv[1], "check", os.path.join(MODEL, "heaters.tnet"), "--case", "thermostats"],
                              capture_output=True, text=True)
    check("declared powers: check exits 1 naming the lens-zone margin", declared.returncode == 1 and
          'VIOLATED: require margin "h[1-6]"' in declared.stdout, declared.stdout.splitlines()[-1])
    designed = subprocess.run([sys.argv[1], "check", os.path.join(MODEL, "designed.tnet")],
                              capture_output=True, text=True)
    check("designed powers meet every requirement when simulated again", designed.returncode == 0,
          designed.stdout.splitlines()[-1])

sys.exit(1 if failures else 0)
