#!/usr/bin/python3
"""Study B numbers from thermnet CSVs (docs/heater_design.md).

  analyse.py --leak LEAK.csv        steady heat leak (thermnet simulate leak.tnet --steady)
  analyse.py RUN.csv [--heated]     min/max optics temperatures, gradients; with --heated also the
                                    thermostat duty cycles and energy, reconstructed from each
                                    zone's temperature with the thermostat's own rule (on below
                                    17 degC, off above 20 degC, starting off).
"""
import sys
import numpy as np

R_M = 0.01  # K/W, meter resistors of leak.tnet
ZONES = [f"zone{i}" for i in range(1, 7)]
POWER = [5.8, 2.1, 1.8, 2.8, 3.0, 2.0]
LENS = ["lens1_c", "lens1_e", "lens2_c", "lens2_e", "lens3_c", "lens3_e"]

d = np.genfromtxt([a for a in sys.argv[1:] if not a.startswith("--")][0], delimiter=",", names=True)
if sys.argv[1] == "--leak":
    lens = sum((20.0 - float(d[z])) / R_M for z in ZONES)
    win = sum((20.0 - float(d[n])) / R_M for n in ("window", "wseat"))
    print(f"steady heat leak at -35 degC: lens {lens:.1f} W, window {win:.1f} W, total {lens + win:.1f} W")
    sys.exit(0)
t = d["time"]
optics = np.vstack([d[n] for n in LENS + ZONES])
for at in (2750, 3000, t[-1]):
    i = int(np.argmin(abs(t - at)))
    print(f"t = {t[i]:.0f} s: optics (lenses + barrel) {optics[:, i].min():.2f} .. {optics[:, i].max():.2f} degC, "
          f"gradient {optics[:, i].max() - optics[:, i].min():.2f} K; window {d['window'][i]:.2f} degC")
late = t >= 2750
print(f"after 2750 s: optics {optics[:, late].min():.2f} .. {optics[:, late].max():.2f} degC; "
      f"largest gradient {np.max(optics[:, late].max(0) - optics[:, late].min(0)):.2f} K; "
      f"largest lens radial gradient {max(np.max(abs(d[f'lens{k}_c'] - d[f'lens{k}_e'])[late]) for k in (1, 2, 3)):.2f} K")
if "--heated" in sys.argv:
    dt = np.diff(t, append=t[-1])
    total = 0.0
    for z, p in zip(ZONES, POWER):
        on, st = False, []
        for T in d[z]:
            if T < 17.0: on = True
            elif T > 20.0: on = False
            st.append(on)
        st = np.array(st)
        e = p * float(np.sum(dt[st]))
        total += e
        print(f"{z}: {p} W, duty cycle over flight (t >= 2750 s) {100 * np.sum(dt[st & late]) / np.sum(dt[late]):.1f} %, "
              f"energy {e / 3600:.2f} Wh")
    print(f"total heater energy {total / 3600:.2f} Wh, mean power over flight {total / (t[-1] - 0):.2f} W")
