#!/usr/bin/env python3
"""An independent continuous-discrete (extended) Kalman filter of the reference test models in
numpy/SciPy: the mean propagated by solve_ivp between samples, the covariance by the model's
Jacobian at the posterior mean discretised by Van Loan's matrix exponential (scipy.linalg.expm),
the update in Joseph form. Evaluated at the parameters thermnet's fit reports (its JSON), it prints
the log-likelihood and writes the one-step-ahead predictions, for comparison with thermnet's.

Usage: kalman_reference.py linear|radiation REPORT.json INPUTS.csv DATA.csv PREDICTIONS_OUT.csv"""
import json, sys
import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import expm

kind, report, inputs_csv, data_csv, out_csv = sys.argv[1:6]
r = json.load(open(report))
par, noise = r["params"], r["noise"]
K0, SIGMA = 273.15, 5.670374419e-8
inp = np.loadtxt(inputs_csv, delimiter=",", skiprows=1)
dat = np.loadtxt(data_csv, delimiter=",", skiprows=1)
ti, Ta, P = inp[:, 0], inp[:, 1] + K0, inp[:, 2]
tk, y = dat[:, 0], dat[:, 1] + K0

if kind == "linear":
    C = np.array([par["Ca"], 6e5])
    def F(t, T):
        ta, p = np.interp(t, ti, Ta), np.interp(t, ti, P)
        qab = par["Gab"] * (T[0] - T[1])
        return np.array([p - qab, qab - par["Gb"] * (T[1] - ta)])
    def dF(t, T):
        g, gb = par["Gab"], par["Gb"]
        return np.array([[-g, g], [g, -g - gb]])
else:
    C = np.array([2e4, 8e4])
    def F(t, T):
        ta, p = np.interp(t, ti, Ta), np.interp(t, ti, P)
        q = SIGMA * par["GR"] * (T[0]**4 - T[1]**4)
        return np.array([p - q, q - par["Gb"] * (T[1] - ta)])
    def dF(t, T):
        k = 4 * SIGMA * par["GR"]
        return np.array([[-k * T[0]**3, k * T[1]**3], [k * T[0]**3, -k * T[1]**3 - par["Gb"]]])

sw = np.array([noise["sigma_w[a]"], noise["sigma_w[b]"]])
sv = noise["sigma_v[a]"]
Qc = np.diag(sw**2)
x = np.array([20 + K0, 20 + K0])
Pm = np.eye(2) * r.get("initial_sd_K", 1.0)**2
ll, t, rows = 0.0, 0.0, []
for k in range(len(tk)):
    if tk[k] > t:
        h = tk[k] - t
        A = dF(t, x) / C[:, None]
        M = np.zeros((4, 4))
        M[:2, :2], M[:2, 2:], M[2:, 2:] = -A * h, Qc * h, A.T * h
        E = expm(M)
        Phi = E[2:, 2:].T
        Qd = Phi @ E[:2, 2:]
        sol = solve_ivp(lambda tt, T: F(tt, T) / C, (t, tk[k]), x, method="DOP853",
                        rtol=1e-12, atol=1e-12)
        x = sol.y[:, -1]
        Pm = Phi @ Pm @ Phi.T + 0.5 * (Qd + Qd.T)
    t = tk[k]
    S = Pm[0, 0] + sv**2
    e = y[k] - x[0]
    rows.append((t, x[0] - K0, np.sqrt(S)))
    ll += -0.5 * (np.log(2 * np.pi) + np.log(S) + e * e / S)
    K = Pm[:, 0] / S
    x = x + K * e
    IKH = np.eye(2) - np.outer(K, [1.0, 0.0])
    Pm = IKH @ Pm @ IKH.T + sv**2 * np.outer(K, K)
with open(out_csv, "w") as f:
    f.write("time,predicted,sd\n")
    for row in rows:
        f.write("%.10g,%.12g,%.12g\n" % row)
print("%.12g" % ll)
