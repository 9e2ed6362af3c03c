#!/usr/bin/python3
"""Hit rate of `thermnet diagnose` on random 72-node, three-case radiating panels (issue 55).

Instance i is drawn from seed S + i, WITHOUT thermnet: a 6 x 11 radiator panel in a vacuum chamber
(tests/diagnose_scenarios/shapes.py's `panel`: every cell radiates to the shroud, one edge bolted to
a cold rail, the conductivity and the emissivity ranged) with six boxes (components) on it, each a
node of its own bolted to its cell and radiating to the shroud, carrying a heater: 66 + 6 = 72
nodes, three 8 h cases at 30 s, 40 nodes measured, 0.3 K noise, the ranged params 10-30 % off (as
bench/diagnosis.csv's B72). ONE hidden effect, its kind by turn (instance i: KINDS[i % 3]):

  missing_link    a conductance between two boxes (a cable, a bracket) that the model lacks
  missing_source  a constant heat gain or loss at a random node (measured or not, 50/50)
  capacity_error  a box's capacity times a factor (a random box, measured or not: a panel cell's
                  15-20 J/K even times 5 moves no reading by 0.3 K, 0.13 K measured on one)

placed and sized by tests/diagnose_scenarios (effects.py, generate.py's scale: the effect alone
moves some measured reading by about 3 K at its peak), integrated by SciPy (truth.py) with noise.
The model handed to thermnet is the nominal one, without the effect.

Each instance is diagnosed by `thermnet diagnose model.tnet --threads T --json report.json --stats`
(a timeout per instance) and scored from the JSON report:
  hit        the first structural finding is the hidden effect: same kind, same place (a link:
             the same two nodes in either order; its mechanism does not decide, as in score.py)
  ambiguous  the hidden effect is one of the first finding's rivals (its `candidates`, the
             "fits as well" set; score.py's first MAX_SET members)
  miss       otherwise, also when there is no structural finding
  timeout / error

It prints and writes (--out, markdown, rewritten after every instance) a table: instance, effect,
truth place, first finding, verdict, wall and CPU seconds (user + system of the child, getrusage),
simulations and refits (the --stats lines); then the hit rate and the (hit + ambiguous) rate with
95 % Clopper-Pearson intervals.

Usage: bench/panel_hit_rate.py THERMNET --instances N --seed S [--threads T] [--keep DIR]
           [--out results.md] [--timeout 600] [--stop-at HH:MM] [--dry-run]
--dry-run generates (and with --keep writes) the instances and prints their truths, no diagnosis.
--keep: an instance folder already there is reused when it holds the same instance (same draw,
same generator source: instance.txt), so instances can be generated ahead with --dry-run.
--stop-at: no instance is started at or after this UTC time of day (the table says so).
"""
from __future__ import annotations

import argparse
import datetime as dt
import hashlib
import inspect
import json
import os
import resource
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import numpy as np
from scipy.stats import beta

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "diagnose_scenarios"))
sys.path.insert(0, HERE)

import effects as fx  # noqa: E402
import generate as gen  # noqa: E402
import score as sc  # noqa: E402
import shapes  # noqa: E402
import truth as tr  # noqa: E402
from diagnosis import stats_counts  # noqa: E402  (bench/diagnosis.py's --stats parser)
from network import Heater, Link, Network, Node, sig4  # noqa: E402

KINDS = ("missing_link", "missing_source", "capacity_error")
NODES, BOXES = 72, 6
ROW = {  # bench/diagnosis.csv's B72, the panel of issue 30
    "shape": "panel", "nodes": NODES, "cases": 3, "measured": 0.556, "noise": 0.3, "impact": 3.0,
    "params": "off", "events": "no",
}
HOURS, OUTPUT = 8.0, 30.0
MAX_SITES = 4  # sites tried per effect, as generate.place
GENERATOR_MODULES = ("effects", "generate", "network", "shapes", "truth", "tnet_writer")


# ---------------------------------------------------------------------------------------------
# The instance


def panel_with_boxes(rng, timing) -> Network:
    """shapes.panel's 66-cell panel (6 x 11) with a box on each of its six components' cells:
    the box is a node (200-800 J/K) bolted to the cell (G 0.5-2 W/K, known), radiating to the
    shroud, and carries the component's heater; the powers are scaled again so the hottest node
    rises 15-25 K."""
    net = shapes.panel(rng, NODES - BOXES, ROW["cases"], False, timing)
    if len(net.heaters) != BOXES:
        raise RuntimeError(f"panel has {len(net.heaters)} components, not {BOXES}")
    for k, h in enumerate(net.heaters):
        box = f"u{k + 1}"
        net.nodes.append(Node(box, sig4(rng.uniform(200.0, 800.0)), f"box {box}"))
        net.links.append(Link(f"ct_{box}", "contact", box, h.node,
                              {"h": sig4(rng.uniform(500.0, 1000.0)), "A": sig4(rng.uniform(1e-3, 2e-3))},
                              f"bolted joint of box {box}"))
        net.links.append(Link(f"r_{box}", "radiation", box, "shroud",
                              {"A": sig4(rng.uniform(0.01, 0.03)), "eps1": sig4(rng.uniform(0.8, 0.9)), "eps2": 1.0}))
        net.heaters[k] = Heater(h.name, box, h.desc)
    shapes._scale_heaters(net, rng.uniform(15.0, 25.0))
    rows, cols = shapes._grid(NODES - BOXES)
    net.name, net.desc = f"panel{NODES}", f"{rows} x {cols} radiator panel in vacuum with {BOXES} boxes"
    return net


def _place_on(net, params, e: fx.Effect, rng, candidates, measured, base_readings, target) -> None:
    """Tries candidate sites (node lists) in random order as generate.place does: the first that,
    scaled, moves a measured reading by 60 % of the target within its bounds; else the one that
    moved it most."""
    best = None
    for j in rng.permutation(len(candidates))[:MAX_SITES]:
        e.nodes = [str(x) for x in rng.permutation(candidates[j])]
        gen.scale(net, params, e, measured, base_readings, target)
        if e.impact >= 0.6 * target and e.strength < fx.BOUNDS[e.key][1]:
            return
        if best is None or e.impact > best[2]:
            best = (e.nodes, e.strength, e.impact)
    e.nodes, e.strength, e.impact = best


def build(index: int, seed: int, hours: float = HOURS, output: float = OUTPUT) -> gen.Scenario:
    """Instance `index` of the study, everything drawn from `seed` in a fixed order."""
    kind = KINDS[index % len(KINDS)]
    row = dict(ROW, id=f"P{index:02d}", seed=seed, effects=kind, timing=(hours * 3600.0, output))
    rng = np.random.default_rng(seed)
    net = panel_with_boxes(rng, row["timing"])
    params = gen.true_params(net, rng, True)
    base_sims = [tr.simulate(net, params, c) for c in net.cases]
    names = [n.name for n in net.nodes]
    measured = set(rng.choice(names, size=int(round(row["measured"] * len(names))), replace=False).tolist())
    e = fx.Effect(kind, bool(rng.uniform() < 0.5), "linear" if kind == "missing_link" else None)
    fx.randomize(e, rng)
    measured = [a for a in names if a in measured]
    base_readings, _, _ = gen._readings(net, params, [], measured, base_sims)
    boxes = [h.node for h in net.heaters]
    if kind == "missing_link":  # a cable or a bracket between two boxes
        pairs = [[a, b] for i, a in enumerate(boxes) for b in boxes[i + 1:] if not net.linked(a, b)]
        _place_on(net, params, e, rng, pairs, measured, base_readings, row["impact"])
    elif kind == "capacity_error":  # a box's mass (a cell's 15-20 J/K times 5 moves no reading 0.3 K)
        _place_on(net, params, e, rng, [[b] for b in boxes], measured, base_readings, row["impact"])
    else:  # a source anywhere, on a node measured or not as drawn (effects.sites)
        gen.place(net, params, e, base_sims, rng, measured, set(), base_readings, row["impact"])
    e.want_measured = e.nodes[0] in measured
    clean, sims, truth_net = gen._readings(net, params, [e], measured)
    sigma = {a: sig4(row["noise"] * rng.uniform(0.8, 1.2)) for a in measured}
    data = [np.round(R + rng.normal(0.0, 1.0, R.shape) * np.array([sigma[a] for a in measured]), 3) for R in clean]
    return gen.Scenario(row, net, params, [e], measured, truth_net, sims, clean, data, sigma)


def describe_effect(t: dict) -> tuple[str, str]:
    """(effect with its size and impact, place) of a truth.json's single effect."""
    e = t["effects"][0]
    vals = ", ".join(f"{k} {v:.4g}" for k, v in e["values"].items())
    where = ", ".join(e["nodes"]) + ("" if e["measured"] or e["kind"] == "missing_link" else " (unmeasured)")
    if e["kind"] == "missing_link":
        where += " (" + ", ".join("m" if a in t["measured"] else "u" for a in e["nodes"]) + ")"
    return f"{e['kind']} {vals} ({e['impact_K']:.2g} K)", where


def fingerprint(index: int, seed: int, hours: float, output: float) -> str:
    """Identifies an instance: its draw and the generator's source (this file's generating
    functions and the scenario modules), so a kept folder is reused only for what would be generated again."""
    h = hashlib.sha256(repr((index, seed, hours, output, KINDS, NODES, BOXES, ROW, MAX_SITES)).encode())
    for fn in (panel_with_boxes, _place_on, build):
        h.update(inspect.getsource(fn).encode())
    scen = os.path.join(HERE, "..", "tests", "diagnose_scenarios")
    for m in GENERATOR_MODULES:
        with open(os.path.join(scen, f"{m}.py"), "rb") as f:
            h.update(f.read())
    return h.hexdigest()


def generated(folder: str, index: int, seed: int, hours: float, output: float) -> dict:
    """The instance's truth, generated into folder unless folder already holds this very instance
    (a kept folder of an earlier run: --keep)."""
    fp = fingerprint(index, seed, hours, output)
    stamp = os.path.join(folder, "instance.txt")
    if os.path.exists(stamp):
        with open(stamp) as f:
            if f.read().strip() == fp:
                with open(os.path.join(folder, "truth.json")) as t:
                    return json.load(t)
    truth = gen.write(build(index, seed, hours, output), folder)
    with open(stamp, "w") as f:
        f.write(fp + "\n")
    return truth


# ---------------------------------------------------------------------------------------------
# Scoring


def _member_text(m: dict) -> str:
    mech = f"/{m['mechanism']}" if m.get("mechanism") else ""
    return f"{m.get('kind')}{mech} [{', '.join(m.get('nodes') or [])}]"


def verdict(report: dict | None, truth: dict) -> tuple[str, str]:
    """('hit' | 'ambiguous' | 'miss', the first finding in words) of a report against the truth's
    single effect; report None: the diagnosis failed (the caller says how)."""
    if report is None:
        return "error", "–"
    found = sc.structural(report)
    if not found:
        return "miss", "none"
    effect, first = truth["effects"][0], found[0]
    members = sc.members(first)
    text = _member_text(first) + (f" (+{len(members) - 1} rivals)" if len(members) > 1 else "")
    if sc.match_member(first, effect, truth) == "full":
        return "hit", text
    if any(sc.match_member(m, effect, truth) == "full" for m in members[1:]):
        return "ambiguous", text
    return "miss", text


def clopper_pearson(k: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """Exact two-sided binomial confidence interval for k successes in n trials."""
    if n == 0:
        return 0.0, 1.0
    a = 1.0 - level
    lo = 0.0 if k == 0 else float(beta.ppf(a / 2, k, n - k + 1))
    hi = 1.0 if k == n else float(beta.ppf(1 - a / 2, k + 1, n - k))
    return lo, hi


def summary(rows: list[dict]) -> list[str]:
    n = len(rows)
    hits = sum(r["verdict"] == "hit" for r in rows)
    amb = sum(r["verdict"] == "ambiguous" for r in rows)
    out = []
    for name, k in (("hit rate", hits), ("hit + ambiguous rate", hits + amb)):
        lo, hi = clopper_pearson(k, n)
        rate = f"{100.0 * k / n:.0f} %" if n else "–"
        out.append(f"- {name}: {k}/{n} = {rate}, 95 % Clopper-Pearson interval {100 * lo:.1f}-{100 * hi:.1f} %")
    counts = {v: sum(r["verdict"] == v for r in rows) for v in ("hit", "ambiguous", "miss", "timeout", "error")}
    out.append("- verdicts: " + ", ".join(f"{v} {c}" for v, c in counts.items()))
    return out


# ---------------------------------------------------------------------------------------------
# Running


def run_diagnose(binary: str, folder: str, threads: int, timeout: float) -> dict:
    """thermnet diagnose in folder, its wall and CPU seconds, --stats counts and report."""
    args = [binary, "diagnose", "model.tnet", "--threads", str(threads), "--json", "report.json", "--stats"]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    with open(os.path.join(folder, "stdout.txt"), "w") as out, open(os.path.join(folder, "stats.txt"), "w+") as err:
        p = subprocess.Popen(args, cwd=folder, stdout=out, stderr=err, start_new_session=True)
        try:
            rc = p.wait(timeout=timeout)
            timed_out = False
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)  # the child's own session: nothing else is touched
            rc = p.wait()
            timed_out = True
        err.seek(0)
        stderr = err.read()
    wall = time.monotonic() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    sims, refits = stats_counts(stderr)
    report = None
    if rc == 0 and not timed_out:
        with open(os.path.join(folder, "report.json")) as f:
            report = json.load(f)
    return {"rc": rc, "timed_out": timed_out, "wall_s": wall, "cpu_s": cpu, "simulations": sims,
            "refits": refits, "report": report, "stderr": stderr}


HEADER = ("| instance | seed | effect (size, impact) | truth place | first finding | verdict | wall s | CPU s "
          "| simulations | refits |\n|---|---|---|---|---|---|---|---|---|---|")


def table_row(r: dict) -> str:
    return (f"| {r['instance']} | {r['seed']} | {r['effect']} | {r['place']} | {r['first']} | {r['verdict']} "
            f"| {r['wall_s']:.1f} | {r['cpu_s']:.1f} | {r['simulations']} | {r['refits']} |")


def write_markdown(path: str, head: list[str], rows: list[dict], tail: list[str]) -> None:
    tmp = f"{path}.tmp{os.getpid()}"
    with open(tmp, "w") as f:
        f.write("\n".join(head + ["", HEADER] + [table_row(r) for r in rows] + [""] + summary(rows) + tail) + "\n")
    os.replace(tmp, path)


def past(stop_at: str | None) -> bool:
    if not stop_at:
        return False
    hh, mm = (int(x) for x in stop_at.split(":"))
    now = dt.datetime.now(dt.timezone.utc)
    return (now.hour, now.minute) >= (hh, mm)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("binary", help="path to thermnet")
    ap.add_argument("--instances", type=int, required=True)
    ap.add_argument("--first", type=int, default=0,
                    help="start at this instance (its seed is --seed plus it): a study continued")
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--keep", help="write the instances into this folder and keep them")
    ap.add_argument("--out", help="also write the markdown table here")
    ap.add_argument("--timeout", type=float, default=600.0, help="seconds per diagnosis")
    ap.add_argument("--stop-at", help="start no instance at or after this UTC time, HH:MM")
    ap.add_argument("--dry-run", action="store_true", help="generate and describe only")
    ap.add_argument("--note", action="append", default=[], help="a line for the markdown's head (repeatable)")
    ap.add_argument("--hours", type=float, default=HOURS, help=argparse.SUPPRESS)  # tests: shorter cases
    ap.add_argument("--output", type=float, default=OUTPUT, help=argparse.SUPPRESS)
    a = ap.parse_args()
    if not 0 <= a.first < a.instances:
        ap.error("--first must be at least 0 and below --instances")
    binary = os.path.abspath(a.binary) if os.sep in a.binary else a.binary  # it runs in the instance's folder
    root = a.keep or tempfile.mkdtemp(prefix="thermnet_panel_")
    argv = [x for k, x in enumerate(sys.argv[1:]) if x != "--note" and (k == 0 or sys.argv[k] != "--note")]
    cmd = shlex.join(["bench/panel_hit_rate.py"] + argv)
    head = ["# `thermnet diagnose` on random 72-node three-case panels: the hit rate (issue 55)", "",
            "Written by bench/panel_hit_rate.py (its doc says what an instance is and how it is scored).", "",
            *[x for n in a.note for x in (n, "")], f"Command: `{cmd}`", f"Started {dt.datetime.now(dt.timezone.utc):%Y-%m-%d %H:%M} UTC; "
            f"instances {a.first}..{a.instances - 1} asked, seeds {a.seed + a.first}..{a.seed + a.instances - 1}, "
            f"--threads {a.threads}, "
            f"timeout {a.timeout:g} s."]
    rows, tail = [], []
    print(HEADER, flush=True)
    try:
        for i in range(a.first, a.instances):
            if past(a.stop_at):
                tail = [f"- stopped before instance {i}: --stop-at {a.stop_at} UTC reached"]
                break
            folder = os.path.join(root, f"P{i:02d}")
            truth = generated(folder, i, a.seed + i, a.hours, a.output)
            effect, place = describe_effect(truth)
            r = {"instance": i, "seed": a.seed + i, "effect": effect, "place": place, "first": "–",
                 "verdict": "dry run", "wall_s": 0.0, "cpu_s": 0.0, "simulations": 0, "refits": 0}
            if not a.dry_run:
                d = run_diagnose(binary, folder, a.threads, a.timeout)
                r.update({k: d[k] for k in ("wall_s", "cpu_s", "simulations", "refits")})
                if d["timed_out"]:
                    r["verdict"] = "timeout"
                elif d["rc"] != 0:
                    r["verdict"], r["first"] = "error", f"exit {d['rc']}"
                else:
                    r["verdict"], r["first"] = verdict(d["report"], truth)
            rows.append(r)
            print(table_row(r), flush=True)
            if a.out and not a.dry_run:
                write_markdown(a.out, head, rows, tail)
    finally:
        if not a.keep:
            shutil.rmtree(root, ignore_errors=True)
    if not a.dry_run:
        for line in summary(rows) + tail:
            print(line)
        if a.out:
            write_markdown(a.out, head, rows, tail)
    return 0


if __name__ == "__main__":
    sys.exit(main())
