#!/usr/bin/python3
"""Checks the scenario generator itself, so that a diagnosis result can be trusted to say
something about thermnet and not about a broken test:

- the truth it integrates with SciPy is the network it writes: `thermnet simulate` of the truth
  written as .tnet agrees within 0.02 K at every node (generate.py --verify);
- the nominal model lints clean with --werror; the data have `time` and exactly the measured
  nodes as columns, the measured fraction is the table's, and the added noise has about the
  table's sigma;
- every ranged param is 10-30 % off its nominal value inside its range (exactly nominal for a
  `nominal` control); every hidden effect moves a measured reading by at least half the table's
  target impact, sits on a measured node or not as the table says, and events exist when needed;
- the same seed gives the same data.

Usage: check_generator.py PATH/TO/thermnet [ID ...]   (default: a fast subset covering every
shape and every effect kind; `all` for the whole table)
"""
import csv
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import generate  # noqa: E402

FAST = ["S09", "S03", "S11", "S13", "S15", "S17", "S23", "S24", "S25", "D01", "D02", "C05"]


def check(row: dict, thermnet: str, folder: str) -> list[str]:
    """The problems found with one scenario (empty: fine)."""
    bad = []
    t = generate.generate(row, folder, thermnet)
    lint = subprocess.run([thermnet, "lint", "--werror", os.path.join(folder, "model.tnet")], capture_output=True, text=True)
    if lint.returncode != 0:
        bad.append(f"model.tnet does not lint clean: {lint.stdout}{lint.stderr}")
    measured = t["measured"]
    if abs(len(measured) / t["nodes"] - row["measured"]) > 0.5 / t["nodes"] + 1e-9:
        bad.append(f"{len(measured)}/{t['nodes']} nodes measured, table says {row['measured']}")
    for case in t["cases"]:
        with open(os.path.join(folder, f"{case}.csv")) as f:
            header = next(csv.reader(f))
        if header != ["time"] + measured:
            bad.append(f"{case}.csv columns {header[:4]}... are not time + the measured nodes")
    if not 0.8 * row["noise"] <= t["noise"]["rms_added"] <= 1.2 * row["noise"]:
        bad.append(f"added noise RMS {t['noise']['rms_added']:.3f} K for sigma {row['noise']} K")
    for name, p in t["params"].items():
        if not p["lo"] <= p["truth"] <= p["hi"]:
            bad.append(f"param {name} truth {p['truth']} outside its range")
        off = abs(p["truth"] / p["nominal"] - 1)
        if row["params"] == "off" and not 0.099 <= off <= 0.301:
            bad.append(f"param {name} is {100 * off:.1f} % off, not 10-30 %")
        if row["params"] == "nominal" and off != 0:
            bad.append(f"param {name} is off in a nominal control")
    wanted = generate.parse_effects(row["effects"])
    if len(wanted) != len(t["effects"]):
        bad.append("not every effect of the table was made")
    for w, e in zip(wanted, t["effects"]):
        if e["impact_K"] < 0.5 * row["impact"]:
            bad.append(f"{e['kind']} {e['nodes']} moves the readings by {e['impact_K']} K only")
        if e["measured"] != (w.want_measured or e["kind"] in ("sensor_lag", "sensor_offset")):
            bad.append(f"{e['kind']} {e['nodes']} is {'' if e['measured'] else 'not '}measured, against the table")
    if ("event_loss" in row["effects"] or row["events"] == "yes") and not os.path.exists(os.path.join(folder, "events.csv")):
        bad.append("no events.csv")
    return bad


def same_data(row: dict) -> bool:
    a, b = generate.build(row), generate.build(row)
    return all(np.array_equal(x, y) for x, y in zip(a.data, b.data)) and a.measured == b.measured


def main() -> int:
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    thermnet, ids = sys.argv[1], sys.argv[2:] or FAST
    rows = {r["id"]: r for r in generate.load_table()}
    if ids == ["all"]:
        ids = list(rows)
    failed = 0
    with tempfile.TemporaryDirectory(prefix="thermnet_check_generator.") as work:
        for i in ids:
            try:
                problems = check(rows[i], thermnet, os.path.join(work, i))
            except Exception as exc:  # the generator or the verification failed: report, go on
                problems = [f"{type(exc).__name__}: {exc}"]
            failed += bool(problems)
            print(f"{'ok  ' if not problems else 'FAIL'} - {i}" + "".join(f"\n       {p}" for p in problems))
        deterministic = same_data(rows[ids[0]])
        print(f"{'ok  ' if deterministic else 'FAIL'} - {ids[0]} built twice from its seed gives the same data")
        failed += not deterministic
    print(f"{len(ids) + 1 - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
