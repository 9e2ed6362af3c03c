#!/usr/bin/python3
"""Independent check of a design of tests/design/design_cli.sh's plate: the two-node network with
its thermostat simulated by SciPy (solve_ivp with switching events), then the band (14..22 degC
from 600 s) and the margin (P / mean power - 1 >= 0.5 from 600 s) checked on the exact switching.

  plate_scipy.py P_WATTS
"""
import sys

import numpy as np
from scipy.integrate import solve_ivp

P = float(sys.argv[1])
C_plate, C_film, G_bond, G_leak = 2000.0, 50.0, 1000.0 * 0.002, 0.5
T_on, T_off, t_end, t_from = 15.0, 18.0, 3000.0, 600.0


def air(t):
    return np.interp(t, [0.0, 500.0], [10.0, -20.0])


def rhs(t, y, on):
    plate, film = y
    q = G_bond * (film - plate)
    return [(q - G_leak * (plate - air(t))) / C_plate, (P * on - q) / C_film]


t, y, on = 0.0, np.array([20.0, 20.0]), 0
on = 1 if y[0] < T_on else 0
ts, plates, energy_after = [], [], 0.0
while t < t_end:
    ev = lambda tt, yy, on=on: yy[0] - (T_off if on else T_on)
    ev.terminal, ev.direction = True, (1 if on else -1)
    sol = solve_ivp(rhs, (t, t_end), y, args=(on,), events=ev, max_step=2.0, rtol=1e-9, atol=1e-9)
    ts.extend(sol.t)
    plates.extend(sol.y[0])
    t1 = sol.t[-1]
    if on:
        energy_after += P * max(0.0, t1 - max(t, t_from))
    t, y = t1, sol.y[:, -1]
    if sol.status == 1:
        on = 1 - on
ts, plates = np.array(ts), np.array(plates)
late = ts >= t_from
lo, hi = plates[late].min(), plates[late].max()
mean = energy_after / (t_end - t_from)
margin = P / mean - 1.0 if mean > 0 else np.inf
print(f"SciPy: plate {lo:.3f} .. {hi:.3f} degC after {t_from:g} s; mean power {mean:.3f} W; "
      f"margin {100 * margin:.1f} %")
sys.exit(0 if 14.0 <= lo and hi <= 22.0 and margin >= 0.5 - 0.005 else 1)
