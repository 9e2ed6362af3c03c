#!/usr/bin/python3
"""The cost of an imported model against a hand-written one of the same size (docs/import.md).

Generates the Thermal Desktop-sized deck of the import tests (127 nodes in eight submodels, 2,500
conductors, four in five radiative, tests/import/sinda_decks.py), imports it, writes the same
network as a person would in plain thermnet, and times `thermnet import`, `thermnet lint` and
`thermnet simulate` (the 2-hour transient, and the steady state) of both, each REPEAT times; prints
the mean CPU time (GNU time counts in 10 ms steps: the mean of many runs resolves less) and the
median wall time.

Usage: bench/import_size.py PATH/TO/thermnet [REPEAT]
"""
import os
import statistics
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "tests", "import"))
from process_time import timed  # noqa: E402
from sinda_decks import hand_written, td_files, thermal_desktop_like  # noqa: E402


def main(argv):
    exe = argv[1]
    repeat = int(argv[2]) if len(argv) > 2 else 5
    d = thermal_desktop_like()
    with tempfile.TemporaryDirectory(prefix="thermnet_import_size_") as tmp:
        files = []
        for name, lines in td_files(d).items():
            files.append(os.path.join(tmp, name))
            with open(files[-1], "w", encoding="utf-8") as f:
                f.write("\n".join(lines) + "\n")
        imported = os.path.join(tmp, "imported.tnet")
        hand = os.path.join(tmp, "hand.tnet")
        with open(hand, "w", encoding="utf-8") as f:
            f.write("\n".join(hand_written(d)) + "\n")
        runs = {
            "import (deck -> .tnet)": [exe, "import", *files, "-o", imported],
            "lint imported": [exe, "lint", "--werror", imported],
            "lint hand-written": [exe, "lint", "--werror", hand],
            "simulate imported (2 h)": [exe, "simulate", imported, "-o", os.devnull],
            "simulate hand-written (2 h)": [exe, "simulate", hand, "-o", os.devnull],
            "steady imported": [exe, "simulate", imported, "--steady", "-o", os.devnull],
            "steady hand-written": [exe, "simulate", hand, "--steady", "-o", os.devnull],
        }
        print(f"{len(d.nodes) - 2} nodes, {len(d.conductors)} conductors "
              f"({sum(c[5] for c in d.conductors)} radiative); {repeat} runs each")
        print(f"{'run':32s} {'mean CPU s':>10s} {'median wall s':>14s}")
        for what, cmd in runs.items():
            cpu, wall = [], []
            for _ in range(repeat):
                t = timed(cmd)
                if t.rc != 0:
                    raise SystemExit(f"{what} failed ({t.rc}): {t.stderr[-2000:]}")
                cpu.append(t.cpu_s)
                wall.append(t.wall_s)
            print(f"{what:32s} {statistics.mean(cpu):10.4f} {statistics.median(wall):14.3f}")
        lines = sum(1 for _ in open(imported, encoding="utf-8"))
        print(f"imported model: {lines} lines, {os.path.getsize(imported)} bytes; hand-written: "
              f"{len(hand_written(d))} lines, {os.path.getsize(hand)} bytes")


if __name__ == "__main__":
    main(sys.argv)
