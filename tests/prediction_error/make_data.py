#!/usr/bin/env python3
"""Data for the prediction criterion's reference tests, made by SciPy (solve_ivp, an integrator
independent of thermnet) from the models' own equations at true values that differ from the
declared ones, with an unmeasured random heat input into node `a` (a random walk of 2 W per
sample, linear between samples: what the models' process noise stands for) and N(0, 0.05 K)
measurement noise on the measured node `a`.

Writes inputs.csv (time, Ta degC, P W), data_linear.csv and data_radiation.csv (time, a degC) into
the folder given as the first argument; and for the diagnosis test, a block heated through a
heater body of its own (3 kJ/K behind 4 W/K, what heater_1node.tnet lacks), sampled every 120 s
for 10 h with N(0, 0.02 K) noise: inputs_heater.csv (time, Ta, P) and data_heater.csv (time, a)."""
import sys, os
import numpy as np
from scipy.integrate import solve_ivp

out = sys.argv[1]
rng = np.random.default_rng(29)
t = np.arange(0.0, 86400.0 + 1, 600.0)
Ta = 10 + 6 * np.sin(2 * np.pi * (t - 30000) / 86400)
P = np.where((t >= 7200) & (t < 43200), 400.0, 0.0)
P = np.where((t >= 57600) & (t < 72000), 250.0, P)
# the heater steps between two samples are ramps in a table: make them so in the truth as well
Q = np.cumsum(rng.normal(0, 2.0, t.size))  # unmeasured heat into a, W
SIGMA = 5.670374419e-8
K0 = 273.15

def inputs(tt):
    return np.interp(tt, t, Ta) + K0, np.interp(tt, t, P) + np.interp(tt, t, Q)

def linear(tt, T):
    ta, p = inputs(tt)
    Ca, Cb, Gab, Gb = 1.1e5, 6e5, 11.0, 2.2
    a, b = T
    return [(p - Gab * (a - b)) / Ca, (Gab * (a - b) - Gb * (b - ta)) / Cb]

def radiation(tt, T):
    ta, p = inputs(tt)
    Ca, Cb, GR, Gb = 2e4, 8e4, 0.045, 1.8
    a, b = T
    q = SIGMA * GR * (a**4 - b**4)
    return [(p - q) / Ca, (q - Gb * (b - ta)) / Cb]

with open(os.path.join(out, "inputs.csv"), "w") as f:
    f.write("time,Ta,P\n")
    for row in zip(t, Ta, P):
        f.write("%.1f,%.10g,%.10g\n" % row)
for name, rhs in (("linear", linear), ("radiation", radiation)):
    sol = solve_ivp(rhs, (0, t[-1]), [20 + K0, 20 + K0], t_eval=t, method="Radau",
                    rtol=1e-10, atol=1e-10, max_step=600)
    y = sol.y[0] - K0 + rng.normal(0, 0.05, t.size)
    with open(os.path.join(out, "data_%s.csv" % name), "w") as f:
        f.write("time,a\n")
        for tt, v in zip(t, y):
            f.write("%.1f,%.10g\n" % (tt, v))

# The heated block with a heater body (the diagnosis test).
th = np.arange(0.0, 36000.0 + 1, 120.0)
Tah = 15 + 1.5 * np.sin(2 * np.pi * th / 20000)
Ph = np.where((th >= 3600) & (th < 14400), 120.0, 0.0)
Ph = np.where((th >= 21600) & (th < 28800), 70.0, Ph)

def heated(tt, T):
    ta, p = np.interp(tt, th, Tah) + K0, np.interp(tt, th, Ph)
    Ca, Ch, Gh, G = 5e4, 3e3, 4.0, 2.0
    a, h = T
    return [(Gh * (h - a) - G * (a - ta)) / Ca, (p - Gh * (h - a)) / Ch]

sol = solve_ivp(heated, (0, th[-1]), [15 + K0, 15 + K0], t_eval=th, method="Radau",
                rtol=1e-10, atol=1e-10, max_step=120)
with open(os.path.join(out, "inputs_heater.csv"), "w") as f:
    f.write("time,Ta,P\n")
    for row in zip(th, Tah, Ph):
        f.write("%.1f,%.10g,%.10g\n" % row)
with open(os.path.join(out, "data_heater.csv"), "w") as f:
    f.write("time,a\n")
    for tt, v in zip(th, sol.y[0] - K0 + rng.normal(0, 0.02, th.size)):
        f.write("%.1f,%.10g\n" % (tt, v))
