#!/usr/bin/env python3
"""A hardware-like thermostat cycle by `thermnet simulate` against SciPy's solve_ivp.

A heater film (50 J/K) glued to its mount (2000 J/K, 1 W/K to 0 degC), the sensor on the mount with
a 30 s lag, minimum on/off times: thermnet integrates the lagged reading as a state with the
temperatures and switches by root-finding (thresholds) and time events (end of a hold). Here SciPy
integrates the same three equations with its own event location, the holds handled by stopping at
their ends: the temperatures at every output time, the switch count, the on time and the heater
energy of the `--energy` report must agree.

Usage: thermostat_scipy.py PATH/TO/thermnet
"""

import csv
import os
import subprocess
import sys
import tempfile

import numpy as np
from scipy.integrate import solve_ivp

C1, C2, G, G2, P = 50.0, 2000.0, 2.0, 1.0, 40.0
ON, OFF, LAG, MIN_ON, MIN_OFF = 18.0, 20.0, 30.0, 300.0, 400.0
DURATION, OUTPUT = 20000.0, 10.0

MODEL = f"""model hardware
boundary amb T = 0
node film C = {C1} T0 = 0
node mount C = {C2} T0 = 0
conductance glue film mount G = {G}
conductance loss mount amb G = {G2}
thermostat th film P = {P} on = {ON} off = {OFF} sense = mount lag = {LAG} [s] min_on = {MIN_ON} [s] min_off = {MIN_OFF} [s]
case c {{ duration = {DURATION}; output = {OUTPUT} }}
"""

TOL = dict(method="LSODA", rtol=1e-12, atol=1e-12)


def rhs(heating):
    def f(_t, y):
        film, mount, reading = y
        return [
            (P * heating - G * (film - mount)) / C1,
            (G * (film - mount) - G2 * mount) / C2,
            (mount - reading) / LAG,
        ]

    return f


def scipy_run():
    """Piecewise solution: (list of dense segments, switch times, on time)."""
    t, y = 0.0, np.array([0.0, 0.0, 0.0])
    heating = y[2] <= ON  # a reading at or below 'on' starts the heater
    last = None
    segments, switches, on_time = [], [], 0.0

    def advance(t_end, events=None):
        nonlocal t, y, on_time
        sol = solve_ivp(rhs(heating), (t, t_end), y, dense_output=True, events=events, **TOL)
        segments.append((t, sol.t[-1], sol.sol))
        if heating:
            on_time += sol.t[-1] - t
        t, y = sol.t[-1], sol.y[:, -1]
        return sol

    def switch():
        nonlocal heating, last
        heating = not heating
        last = t
        switches.append(t)

    while t < DURATION:
        if last is not None:
            hold_end = last + (MIN_ON if heating else MIN_OFF)
            if hold_end > t:
                advance(min(hold_end, DURATION))
                if t >= DURATION:
                    break
                beyond = y[2] >= OFF if heating else y[2] <= ON
                if beyond:
                    switch()
                    continue
        level = OFF if heating else ON

        def crossing(_t, yy, level=level):
            return yy[2] - level

        crossing.terminal = True
        crossing.direction = 1 if heating else -1
        sol = advance(DURATION, [crossing])
        if sol.status == 1:
            switch()
    return segments, switches, on_time


def at(segments, time):
    for a, b, sol in segments:
        if a <= time <= b and b > a:
            return sol(time)
    raise ValueError(time)


def main():
    tn = sys.argv[1]
    segments, switches, on_time = scipy_run()
    held = sum(1 for k in range(1, len(switches))
               if abs(switches[k] - switches[k - 1] - (MIN_OFF if k % 2 == 1 else MIN_ON)) < 1e-9)
    print(f"scipy: {len(switches)} switches ({held} at the end of a hold), on time {on_time:.6f} s")
    failures = []
    if held == 0 or held == len(switches) - 1:
        failures.append("the case should mix switches at thresholds and at hold ends")
    with tempfile.TemporaryDirectory() as work:
        model = os.path.join(work, "hardware.tnet")
        with open(model, "w") as f:
            f.write(MODEL)
        csv_path, energy_path = os.path.join(work, "out.csv"), os.path.join(work, "energy.txt")
        subprocess.run([tn, "simulate", model, "-o", csv_path, "--energy", energy_path,
                        "--rtol", "1e-12", "--atol", "1e-12"], check=True)
        with open(csv_path) as f:
            rows = list(csv.DictReader(f))
        with open(energy_path) as f:
            report = f.read()
    worst = 0.0
    for row in rows:
        t = float(row["time"])
        ref = at(segments, t)
        worst = max(worst, abs(float(row["film"]) - ref[0]), abs(float(row["mount"]) - ref[1]))
    print(f"{len(rows)} rows, worst temperature difference {worst:.3e} K")
    if worst > 1e-6:  # both solvers at tolerances of 1e-12
        failures.append(f"temperatures differ by {worst} K")
    line = next(l for l in report.splitlines() if l.startswith("th"))
    energy, on, _duty, count = line.split()[-4:]
    print(f"thermnet: {count} switches, on time {on} s, energy {energy} J")
    if int(count) != len(switches):
        failures.append(f"switch count {count}, scipy {len(switches)}")
    if abs(float(on) - on_time) > 1e-5 * on_time:
        failures.append(f"on time {on}, scipy {on_time}")
    if abs(float(energy) - P * on_time) > 1e-5 * P * on_time:
        failures.append(f"energy {energy}, scipy {P * on_time}")
    for f in failures:
        print("FAIL -", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
