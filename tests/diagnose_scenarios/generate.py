#!/usr/bin/python3
"""Builds one diagnosis scenario of scenarios.csv, reproducibly from its seed, WITHOUT thermnet.

Writes into OUTDIR:
  model.tnet   the nominal model a user would have: ranged params at their nominal values,
               cases with heater schedules and boundary changes, a `data` file per case
  runN.csv     measured data of case runN: `time` and one column per MEASURED node only
  events.csv   (scenarios with events) case,event,start,end -- when the box's lid was open [s]
  truth.json   what the data really come from: true param values, hidden effects with their
               sizes and impacts, the measured nodes, the noise

The truth is the nominal network with every ranged param moved 10-30 % off its nominal value
(inside its range; unless the scenario's params column says `nominal`), plus the scenario's hidden
effects (effects.py), integrated by SciPy (truth.py), read by the sensors (lag, offset) and
perturbed by Gaussian noise (each sensor sigma times 0.8-1.2).

With --verify THERMNET the generator checks itself: it writes the truth as a .tnet (true params,
the structural effects as elements; an event loss cannot be written and is left out) and requires
`thermnet simulate` of it to agree with its own SciPy integration within 0.02 K at every node.

Usage: generate.py ID OUTDIR [--table scenarios.csv] [--verify PATH/TO/thermnet]
"""
from __future__ import annotations

import argparse
import csv
import hashlib
import json
import os
import subprocess
import sys
from dataclasses import dataclass

import numpy as np

import effects as fx
import shapes
import truth as tr
from network import SIGMA_SB, ZERO_C, Network, conductance, sig4
from tnet_writer import write_tnet

HERE = os.path.dirname(os.path.abspath(__file__))
TABLE = os.path.join(HERE, "scenarios.csv")
VERIFY_TOLERANCE = 0.02  # K


def load_table(path: str = TABLE) -> list[dict]:
    with open(path) as f:
        rows = [r for r in csv.DictReader(line for line in f if not line.startswith("#"))]
    for r in rows:
        r["nodes"], r["seed"], r["cases"] = int(r["nodes"]), int(r["seed"]), int(r["cases"])
        r["measured"], r["noise"], r["impact"] = float(r["measured"]), float(r["noise"]), float(r["impact"])
        # optional columns (bench/diagnosis.csv): hours per case and seconds between samples
        r["timing"] = (float(r.get("hours") or shapes.DURATION / 3600.0) * 3600.0,
                       float(r.get("output") or shapes.OUTPUT))
    return rows


def parse_effects(spec: str) -> list[fx.Effect]:
    """'missing_link:radiation@u;sensor_offset@m' -> effects ('' or 'none': no effect)."""
    out = []
    for item in filter(None, (s.strip() for s in spec.split(";"))):
        if item == "none":
            continue
        what, _, where = item.partition("@")
        kind, _, mech = what.partition(":")
        if kind not in fx.KINDS or where not in ("m", "u"):
            raise ValueError(f"bad effect '{item}'")
        out.append(fx.Effect(kind, where == "m", mech or ("linear" if kind == "missing_link" else None)))
    return out


def true_params(net: Network, rng, off: bool) -> dict[str, float]:
    """Every ranged param 10-30 % off its nominal value, inside its range."""
    out = {}
    for p in net.params:
        if not off:
            out[p.name] = p.nominal
            continue
        d = rng.uniform(0.1, 0.3)
        up = p.nominal * (1 + d)
        v = up if (rng.uniform() < 0.5 and up <= p.hi) or p.nominal * (1 - d) < p.lo else p.nominal * (1 - d)
        out[p.name] = sig4(v)
    return out


def _readings(net, params, eff, measured, cases_sims=None):
    """Noise-free sensor readings per case, [time, measured node], and the simulations."""
    truth, lags, offsets = fx.apply(net, eff, params)
    sims = cases_sims or [tr.simulate(truth, params, c, lags) for c in truth.cases]
    idx = {n.name: i for i, n in enumerate(truth.nodes)}
    out = []
    for times, T, sensors in sims:
        cols = [sensors[a] if a in sensors else T[:, idx[a]] for a in measured]
        R = np.column_stack(cols)
        for k, a in enumerate(measured):
            R[:, k] += offsets.get(a, 0.0)
        out.append(R)
    return out, sims, truth


def _node_conductance(net: Network, params, a: str) -> float:
    lin = 4.0 * SIGMA_SB * (20.0 + ZERO_C) ** 3
    return sum(conductance(lk, params) * (lin if lk.kind == "radiation" else 1.0)
               for lk in net.links if a in (lk.a, lk.b))


def _first_strength(net: Network, params, e: fx.Effect) -> float:
    g = _node_conductance(net, params, e.nodes[0])
    return {
        "missing_link/linear": 0.3 * g, "missing_link/radiation": 0.3 * g / 5.5,
        "missing_source": 2.0 * g, "capacity_error": 0.5, "heater_gain": 0.25, "sensor_lag": 300.0,
        "heater_mass": 600.0, "event_loss": 1.0 * g,
        "wall_mass": 1200.0, "hidden_mass": 0.5, "input_split": 0.4,
    }[e.key]


def scale(net, params, e: fx.Effect, measured, base_readings, target: float) -> None:
    """Sets e.strength so that e alone moves a measured reading by about `target` K at its peak
    (a few proportional steps, within the kind's bounds) and records the impact reached."""
    if e.kind == "sensor_offset":  # thermocouple offsets are rarely above 2 K
        e.strength = sig4(e.bounded(0.5 * target))
        e.impact = e.strength
        return
    x = sig4(e.bounded(_first_strength(net, params, e)))
    for _ in range(4):
        e.strength = x
        R, _, _ = _readings(net, params, [e], measured)
        e.impact = float(max(np.abs(r - b).max() for r, b in zip(R, base_readings)))
        if abs(e.impact / target - 1.0) < 0.2:
            return
        ratio = target / e.impact if e.impact > 1e-9 else 100.0
        nxt = sig4(e.bounded(x * ratio))
        if nxt == x:
            return
        x = nxt


def _tied(net: Network, e: fx.Effect) -> list[str]:
    """The few nodes an effect can sit on (a heater's, the box's inside air), or [] for any."""
    if e.kind in ("heater_gain", "heater_mass", "input_split"):
        return [h.node for h in net.heaters]
    if e.kind == "event_loss" and any(n.name == "air_in" for n in net.nodes):
        return ["air_in"]
    return []


def _make_room(net: Network, e: fx.Effect, measured: set[str], rng) -> None:
    """An effect tied to a few nodes needs one of them measured (or not) as the table says: if
    none is, one of them and another node swap their sensors."""
    tied = _tied(net, e)
    if not tied:
        return
    want = e.want_measured
    if any((a in measured) == want for a in tied):
        return
    a = tied[int(rng.integers(len(tied)))]
    others = [n.name for n in net.nodes if n.name not in tied and (n.name in measured) == want]
    (measured.add if want else measured.discard)(a)
    swap = str(rng.choice(others))
    (measured.discard if want else measured.add)(swap)


def place(net, params, e: fx.Effect, base_sims, rng, measured, taken, base_readings, target) -> None:
    """Tries e's candidate sites in turn (at most 4) until, scaled, it moves a measured reading by
    at least 60 % of the target impact with a size inside its bounds (not stuck at the upper one);
    keeps the site with the largest impact otherwise."""
    best = None
    for nodes, element in fx.sites(net, e, base_sims, rng, set(measured), taken)[:4]:
        e.nodes, e.element = nodes, element
        scale(net, params, e, measured, base_readings, target)
        if e.impact >= 0.6 * target and e.strength < fx.BOUNDS[e.key][1]:
            best = (nodes, element, e.strength, e.impact)
            break
        if best is None or e.impact > best[3]:
            best = (nodes, element, e.strength, e.impact)
    if best is None:
        raise RuntimeError(f"no site for {e.key} ({'on' if e.want_measured else 'off'} a sensor)")
    e.nodes, e.element, e.strength, e.impact = best
    taken.add(e.nodes[0])


def _write_csv(path, times, names, R):
    with open(path, "w") as f:
        f.write("time," + ",".join(names) + "\n")
        for t, row in zip(times, R):
            f.write(f"{t:g}," + ",".join(f"{v:.3f}" for v in row) + "\n")


@dataclass
class Scenario:
    """A scenario built in memory: the nominal network, the truth and the measured data."""

    row: dict
    net: Network  # nominal
    params: dict[str, float]  # true values of the ranged params
    effects: list[fx.Effect]
    measured: list[str]  # in model order
    truth_net: Network
    sims: list  # truth per case: (times, T[time, node], {lagged node: reading})
    clean: list[np.ndarray]  # noise-free readings per case [time, measured node]
    data: list[np.ndarray]  # measured data per case (readings + noise, rounded to 1 mK)
    sigma: dict[str, float]  # noise sigma of each sensor


def build(row: dict) -> Scenario:
    """Builds the scenario of a table row (everything drawn from its seed, in a fixed order)."""
    rng = np.random.default_rng(row["seed"])
    events = row["events"] == "yes" or "event_loss" in row["effects"]
    net = shapes.build(row["shape"], row["nodes"], rng, row["cases"], events, row.get("timing", shapes.TIMING))
    params = true_params(net, rng, row["params"] == "off")
    eff = parse_effects(row["effects"])
    base_sims = [tr.simulate(net, params, c) for c in net.cases]
    names = [n.name for n in net.nodes]
    measured = set(rng.choice(names, size=int(round(row["measured"] * len(names))), replace=False).tolist())
    for e in eff:
        fx.randomize(e, rng)
        _make_room(net, e, measured, rng)
    measured = [a for a in names if a in measured]  # in model order
    base_readings, _, _ = _readings(net, params, [], measured, base_sims)
    taken: set[str] = set()
    for e in sorted(eff, key=lambda e: not _tied(net, e)):  # effects tied to a few nodes first
        place(net, params, e, base_sims, rng, measured, taken, base_readings, row["impact"])
    clean, sims, truth_net = _readings(net, params, eff, measured)
    sigma = {a: sig4(row["noise"] * rng.uniform(0.8, 1.2)) for a in measured}
    data = [np.round(R + rng.normal(0.0, 1.0, R.shape) * np.array([sigma[a] for a in measured]), 3) for R in clean]
    return Scenario(row, net, params, eff, measured, truth_net, sims, clean, data, sigma)


def data_checksum(s: Scenario) -> str:
    """Identifies the scenario's measured data (changes whenever the generator's output does)."""
    h = hashlib.sha256()
    for d in s.data:
        h.update(np.ascontiguousarray(d).tobytes())
    return h.hexdigest()[:16]


def write(s: Scenario, outdir: str) -> dict:
    """Writes model.tnet, the data, events.csv and truth.json into outdir; returns the truth."""
    row, net, params = s.row, s.net, s.params
    os.makedirs(outdir, exist_ok=True)
    for case, (times, _, _), data in zip(net.cases, s.sims, s.data):
        _write_csv(os.path.join(outdir, f"{case.name}.csv"), times, s.measured, data)
    header = (f"Scenario {row['id']}: the nominal model ({net.desc}) of a diagnosis scenario,\n"
              f"written by tests/diagnose_scenarios/generate.py (seed {row['seed']}). The data files come\n"
              f"from an independent SciPy simulation of a truth that differs from this model.")
    write_tnet(net, os.path.join(outdir, "model.tnet"), header)
    events = any(c.events for c in net.cases)
    if events:
        with open(os.path.join(outdir, "events.csv"), "w") as f:
            f.write("case,event,start,end\n")
            for c in net.cases:
                for name, t0, t1 in c.events:
                    f.write(f"{c.name},{name},{t0:g},{t1:g}\n")
    added = np.concatenate([(d - R).ravel() for d, R in zip(s.data, s.clean)])
    truth = {
        "id": row["id"], "shape": row["shape"], "network": net.desc, "nodes": len(net.nodes), "seed": row["seed"],
        "checksum": data_checksum(s),
        "cases": [c.name for c in net.cases], "measured": s.measured,
        "noise": {"sigma": row["noise"], "per_sensor": s.sigma, "rms_added": float(np.sqrt(np.mean(added**2)))},
        "params": {p.name: {"nominal": p.nominal, "truth": params[p.name], "lo": p.lo, "hi": p.hi,
                            "off_percent": round(100 * (params[p.name] / p.nominal - 1), 1)} for p in net.params},
        "effects": [{"kind": e.kind, "mechanism": e.mechanism, "nodes": e.nodes, "element": e.element,
                     "values": {k: sig4(v) for k, v in e.values(net, params).items()},
                     "impact_K": round(e.impact, 3), "measured": e.nodes[0] in s.measured} for e in s.effects],
        "control": None if s.effects else ("params" if row["params"] == "off" else "nothing"),
        "events": {c.name: [list(ev) for ev in c.events] for c in net.cases} if events else {},
        "heaters": {h.name: h.node for h in net.heaters},
        "constant_heaters": [h.name for h in net.heaters  # one power in every case: a gain is a source
                             if len({v for c in net.cases for _, v in c.heater_P[h.name].points}) == 1],
    }
    with open(os.path.join(outdir, "truth.json"), "w") as f:
        json.dump(truth, f, indent=1)
    return truth


def generate(row: dict, outdir: str, thermnet: str | None = None) -> dict:
    """Builds and writes the scenario; with thermnet, verifies the truth against it."""
    s = build(row)
    truth = write(s, outdir)
    if thermnet:
        truth["verify_max_diff_K"] = verify(s.truth_net, s.params, s.sims, outdir, thermnet)
    return truth


def verify(truth_net: Network, params, sims, outdir: str, thermnet: str) -> float:
    """Largest |thermnet simulate - SciPy| over every node, time and case of the truth (without an
    event loss, which .tnet cannot state); raises when it exceeds VERIFY_TOLERANCE."""
    net = truth_net.copy()
    had_events = any(lk.during_event for lk in net.links)
    net.links = [lk for lk in net.links if not lk.during_event]
    if had_events:
        sims = [tr.simulate(net, params, c) for c in net.cases]
    vdir = os.path.join(outdir, "verify")
    os.makedirs(vdir, exist_ok=True)
    path = os.path.join(vdir, "truth.tnet")
    write_tnet(net, path, "the truth, for the generator's self-check", params, with_data=False)
    worst = 0.0
    for case, (times, T, _) in zip(net.cases, sims):
        out = os.path.join(vdir, f"{case.name}.csv")
        r = subprocess.run([thermnet, "simulate", path, "--case", case.name, "-o", out],
                           capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(f"thermnet simulate {path}: {r.stderr}")
        with open(out) as f:
            head = f.readline().strip().split(",")
        sim = np.loadtxt(out, delimiter=",", skiprows=1)
        col = {h: i for i, h in enumerate(head)}
        for k, nd in enumerate(net.nodes):
            ours = np.interp(sim[:, 0], times, T[:, k])
            worst = max(worst, float(np.abs(sim[:, col[nd.name]] - ours).max()))
    if worst > VERIFY_TOLERANCE:
        raise RuntimeError(f"thermnet and SciPy disagree on the truth by {worst:.4f} K (> {VERIFY_TOLERANCE} K)")
    return worst


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("id")
    ap.add_argument("outdir")
    ap.add_argument("--table", default=TABLE)
    ap.add_argument("--verify", metavar="THERMNET")
    a = ap.parse_args()
    rows = {r["id"]: r for r in load_table(a.table)}
    if a.id not in rows:
        print(f"generate.py: no scenario '{a.id}' in {a.table}", file=sys.stderr)
        return 2
    t = generate(rows[a.id], a.outdir, a.verify)
    eff = "; ".join(f"{e['kind']} {e['nodes']} {e['values']} (impact {e['impact_K']} K)" for e in t["effects"]) or t["control"]
    print(f"{a.id}: {t['network']}, {len(t['measured'])}/{t['nodes']} measured; {eff}"
          + (f"; verified, max |thermnet - SciPy| = {t['verify_max_diff_K']:.2g} K" if a.verify else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
