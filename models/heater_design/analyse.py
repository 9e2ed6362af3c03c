#!/usr/bin/python3
"""Study B numbers from thermnet CSVs (docs/heater_design.md).

  analyse.py --leak FLOWS.csv      heat leak at the cold case, from the heat flows of
                                    `thermnet simulate leak.tnet --flows FLOWS.csv` at t = 0 (every
                                    part at 20 degC): the paths to the air of optics.tnet summed per
                                    part, in total and per heating zone next to the zone's heater
  analyse.py RUN.csv [--heated FLOWS.csv]
                                    min/max optics temperatures and gradients; with --heated also
                                    the duty cycle and energy of every heater, read from the heater
                                    powers of `thermnet simulate --flows FLOWS.csv` (column
                                    NAME@NODE: the heater's power into its node, 0 while off)
"""
import os
import re
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ZONES = [f"zone{i}" for i in range(1, 7)]
HEATERS = [(f"h{i}", z, p) for i, (z, p) in enumerate(zip(ZONES, [5.8, 2.1, 1.8, 2.8, 3.0, 2.0]), 1)]
LENS = ["lens1_c", "lens1_e", "lens2_c", "lens2_e", "lens3_c", "lens3_e"]
T_CLIMB = 2750.0  # s, end of the climb: the flight starts


def leak_paths() -> dict:
    """The elements of optics.tnet that end at the air, by the part they leave: {part: [names]}."""
    paths = {}
    for line in open(os.path.join(HERE, "optics.tnet")):
        m = re.match(r"\s*\w+\s+(\w+)\s+(\w+)\s+air\b", line)
        if m:
            paths.setdefault(m.group(2), []).append(m.group(1))
    return paths


def leaks(flows_csv: str) -> dict:
    """Heat (W) each part loses to the air at t = 0 of `simulate leak.tnet --flows`: the sum of its
    paths' flows (each positive from its first node, the part, to the air)."""
    f = np.genfromtxt(flows_csv, delimiter=",", names=True, deletechars="")
    assert float(np.atleast_1d(f["time"])[0]) == 0.0
    return {part: sum(float(np.atleast_1d(f[e])[0]) for e in names) for part, names in leak_paths().items()}


def print_leaks(flows_csv: str) -> None:
    q = leaks(flows_csv)
    lens = sum(q[z] for z in ZONES)
    win = q["window"] + q["wseat"]
    print(f"heat leak at -35 degC, optics at 20 degC: lens {lens:.2f} W, window {win:.2f} W, total {lens + win:.2f} W")
    print("per zone (heater): " + ", ".join(f"{z} {q[z]:.2f} W ({p:g} W)" for _, z, p in HEATERS[:6]))
    print("paths: " + "; ".join(f"{part} {' '.join(names)}" for part, names in leak_paths().items()))


def print_run() -> None:
    d = np.genfromtxt(sys.argv[1], delimiter=",", names=True)
    t = d["time"]
    optics = np.vstack([d[n] for n in LENS + ZONES])
    lenses, barrel = optics[:len(LENS)], optics[len(LENS):]
    for at in (T_CLIMB, 3000, t[-1]):
        i = int(np.argmin(abs(t - at)))
        print(f"t = {t[i]:.0f} s: lenses {lenses[:, i].min():.2f} .. {lenses[:, i].max():.2f} degC (mean {lenses[:, i].mean():.2f}), "
              f"barrel {barrel[:, i].min():.2f} .. {barrel[:, i].max():.2f} degC; optics gradient "
              f"{optics[:, i].max() - optics[:, i].min():.2f} K; window {d['window'][i]:.2f} degC")
    late = t >= T_CLIMB
    print(f"flight (t >= {T_CLIMB:.0f} s): optics {optics[:, late].min():.2f} .. {optics[:, late].max():.2f} degC; "
          f"largest gradient {np.max(optics[:, late].max(0) - optics[:, late].min(0)):.2f} K; "
          f"largest lens radial gradient {max(np.max(abs(d[f'lens{k}_c'] - d[f'lens{k}_e'])[late]) for k in (1, 2, 3)):.2f} K; "
          f"window {d['window'][late].min():.2f} .. {d['window'][late].max():.2f} degC")
    if "--heated" in sys.argv:
        flows = np.genfromtxt(sys.argv[sys.argv.index("--heated") + 1], delimiter=",", names=True,
                              deletechars="")
        assert np.array_equal(flows["time"], t), "the flows and temperatures come from different runs"
        # Each sample's state holds until the next sample: a switch is placed to within one output step.
        dt = np.diff(t, append=t[-1])
        total = 0.0
        # Every heater column NAME@NODE of the flows; its power is the largest value it takes.
        heaters = [(c.split("@")[0], c.split("@")[1], float(np.max(flows[c])))
                   for c in flows.dtype.names if "@" in c]
        window_energy = 0.0
        for name, node, p in heaters:
            on = flows[f"{name}@{node}"] > 0.0
            e = p * float(np.sum(dt[on]))
            total += e
            if node == "window":
                window_energy = e
            switches = int(np.count_nonzero(on[1:] != on[:-1]))
            print(f"{name} on {node}, {p:g} W: duty cycle {100 * np.sum(dt[on & late]) / np.sum(dt[late]):.1f} % over the "
                  f"flight, {100 * np.sum(dt[on]) / np.sum(dt):.1f} % overall, {switches} on/off changes, energy {e / 3600:.2f} Wh")
        lens_e = total - window_energy
        print(f"heater energy over {t[-1]:.0f} s: lens barrel {lens_e / 3600:.2f} Wh (mean {lens_e / t[-1]:.2f} W), "
              f"window {(total - lens_e) / 3600:.2f} Wh, total {total / 3600:.2f} Wh (mean {total / t[-1]:.2f} W); "
              f"output step {np.median(np.diff(t)):g} s")


if __name__ == "__main__":
    if sys.argv[1] == "--leak":
        print_leaks(sys.argv[2])
    else:
        print_run()
