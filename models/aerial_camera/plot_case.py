#!/usr/bin/python3
"""SVG plot of one case of study A (workflow.sh step 5): measured window barrel and lens 1 centre
against the nominal and the calibrated extended model. thermnet's own plots show either simulated
nodes only (simulate --plot) or every node at once (calibrate --plot); this one picks two nodes.

Usage: plot_case.py MEASURED.csv NOMINAL.csv EXTENDED.csv OUT.svg TITLE T_OFF
(T_OFF: heater stop time in s, marked by a vertical line)
"""
import sys

import numpy as np

mea, nom, ext = (np.genfromtxt(p, delimiter=",", names=True) for p in sys.argv[1:4])
out, title, t_off = sys.argv[4], sys.argv[5], float(sys.argv[6])
NODES = [("wbarrel", "window barrel", "#1f77b4"), ("lens1_c", "lens 1 centre", "#d62728")]
W, H, L, R, TOP, B = 960, 460, 60, 290, 40, 50
t_max = mea["time"][-1] / 3600
ys = np.concatenate([d[n] for d in (mea, nom, ext) for n, _, _ in NODES])
y0, y1 = np.floor(ys.min() / 5) * 5, np.ceil(ys.max() / 5) * 5
def px(t, y):
    return L + (W - L - R) * t / 3600 / t_max, TOP + (H - TOP - B) * (y1 - y) / (y1 - y0)
svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
       f'<rect width="{W}" height="{H}" fill="white"/>',
       f'<text x="{(W - R + L) / 2}" y="22" text-anchor="middle" font-size="14" font-weight="bold">{title}</text>']
for y in np.arange(y0, y1 + 0.1, 5):
    a, b = px(0, y)
    svg.append(f'<line x1="{L}" y1="{b:.1f}" x2="{W - R}" y2="{b:.1f}" stroke="#ddd"/>'
               f'<text x="{L - 6}" y="{b + 4:.1f}" text-anchor="end">{y:g}</text>')
for h in range(int(t_max) + 1):
    a, b = px(h * 3600, y0)
    svg.append(f'<line x1="{a:.1f}" y1="{TOP}" x2="{a:.1f}" y2="{b:.1f}" stroke="#ddd"/>'
               f'<text x="{a:.1f}" y="{b + 16:.1f}" text-anchor="middle">{h}</text>')
svg.append(f'<text x="{(W - R + L) / 2}" y="{H - 10}" text-anchor="middle">time [h]</text>'
           f'<text x="16" y="{H / 2}" transform="rotate(-90 16 {H / 2})" text-anchor="middle">temperature [°C]</text>')
a, b = px(t_off, y0)
svg.append(f'<line x1="{a:.1f}" y1="{TOP}" x2="{a:.1f}" y2="{b:.1f}" stroke="#555" stroke-dasharray="2,3"/>'
           f'<text x="{a + 4:.1f}" y="{TOP + 12}" fill="#555">heater off</text>')
legend = []
for n, label, col in NODES:
    for d, dash, what in ((nom, "6,4", "nominal model"), (ext, "", "extended, calibrated (lm)")):
        pts = " ".join("%.1f,%.1f" % px(t, y) for t, y in zip(d["time"], d[n]))
        svg.append(f'<polyline points="{pts}" fill="none" stroke="{col}" stroke-width="1.8" stroke-dasharray="{dash}"/>')
        legend.append((f"{label}, {what}", col, dash, False))
    for t, y in zip(mea["time"], mea[n]):
        a, b = px(t, y)
        svg.append(f'<circle cx="{a:.1f}" cy="{b:.1f}" r="2.2" fill="none" stroke="{col}"/>')
    legend.append((f"{label}, measured (synthetic)", col, "", True))
for i, (text, col, dash, marker) in enumerate(legend):
    y = TOP + 10 + 18 * i
    x = W - R + 12
    svg.append(f'<circle cx="{x + 12}" cy="{y}" r="2.5" fill="none" stroke="{col}"/>' if marker else
               f'<line x1="{x}" y1="{y}" x2="{x + 24}" y2="{y}" stroke="{col}" stroke-width="1.8" stroke-dasharray="{dash}"/>')
    svg.append(f'<text x="{x + 30}" y="{y + 4}" font-size="11">{text}</text>')
svg.append("</svg>\n")
open(out, "w").write("\n".join(svg))
