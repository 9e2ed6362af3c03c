#!/usr/bin/python3
"""Where the whole `thermnet simulate` process's time goes on the benchmark plate, beside SciPy's
solve of the same network (issue 55: the 10,000-node process at or under 0.1 x SciPy's solve).

process_parts.py --thermnet PATH [--nodes 10000] [--repeat 7] [--workdir DIR] [--results FILE]

Each part is a whole process timed by GNU time; the parts run interleaved, one run of each per
round, so that a change in the machine's speed during the measurement falls on all of them alike,
and each is reported as the median (and range) over --repeat rounds:

  start-up     `thermnet --version`: the executable and its libraries loaded, static set-up
  lint         `thermnet lint plate.tnet`: read, parse, elaborate and the lint checks
  load+build   `simulate --duration 1 --output 1`: the front end, the network build, a one-second
               solve and a CSV of two rows
  whole        `simulate --output 3600 --stats` at the default tolerance (1e-6) and at
               rtol = atol = 1e-5 (bench/run.py's matched-accuracy run on this plate); its solve is
               the --stats wall time of the integration
  SciPy        bench/scipy_reference.py: solve_ivp BDF at rtol 1e-5, atol 1e-6 (bench/run.py's
               matched-accuracy run), the solve alone (JSON loading and assembly excluded)

The ratio is the whole thermnet process over SciPy's solve.
"""
import argparse
import os
import re
import statistics
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import plate  # noqa: E402
from process_time import timed  # noqa: E402

PY = "/usr/bin/python3"


def solve_wall(t):
    """The integration's wall time that `thermnet simulate --stats` prints (standard error)."""
    m = re.search(r"([0-9.]+) s wall", t.stderr)
    return float(m.group(1)) if m else float("nan")


def scipy_solve(t):
    """solve_ivp's wall time that bench/scipy_reference.py prints (standard output)."""
    m = re.search(r"wall_s ([0-9.eE+-]+)", t.stdout)
    return float(m.group(1)) if m else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--thermnet", required=True)
    ap.add_argument("--nodes", type=int, default=10000)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--workdir", default="/tmp/thermnet-bench-parts")
    ap.add_argument("--results", help="Markdown file to write (default: print only)")
    a = ap.parse_args()
    if a.repeat < 1:
        sys.exit("process_parts.py: --repeat must be at least 1")
    if a.nodes < 2:
        sys.exit("process_parts.py: --nodes must be at least 2")
    exe = os.path.abspath(a.thermnet)
    rows, cols = plate.shape_for_nodes(a.nodes)
    base, _ = plate.generate(rows, cols, a.workdir, a.nodes)
    tnet, out = base + ".tnet", base + ".parts.csv"
    dur = plate.PARAMS["DURATION"]
    sim = [exe, "simulate", tnet, "-o", out]
    parts = [
        ("start-up (`--version`)", [exe, "--version"], None),
        ("lint", [exe, "lint", tnet], None),
        ("load+build (`--duration 1`)", sim + ["--duration", "1", "--output", "1"], None),
        ("whole, default tolerance", sim + ["--output", f"{dur:g}", "--stats"], solve_wall),
        ("whole, rtol = atol = 1e-5", sim + ["--output", f"{dur:g}", "--stats", "--rtol", "1e-5",
                                             "--atol", "1e-5"], solve_wall),
        ("SciPy BDF solve, rtol 1e-5 atol 1e-6",
         [PY, os.path.join(HERE, "scipy_reference.py"), base + ".json", "--out",
          base + ".parts_scipy.txt", "--rtol", "1e-5", "--atol", "1e-6"], scipy_solve),
    ]
    wall = {p[0]: [] for p in parts}
    cpu = {p[0]: [] for p in parts}
    inner = {p[0]: [] for p in parts}
    for r in range(a.repeat):
        for name, cmd, solve in parts:
            t = timed(cmd)
            if t.rc != 0:
                sys.exit(f"process_parts.py: {' '.join(cmd)} exited {t.rc}: {t.stderr[-2000:]}")
            wall[name].append(t.wall_s)
            cpu[name].append(t.cpu_s)
            if solve:
                inner[name].append(solve(t))
        print(f"round {r + 1}/{a.repeat} done", flush=True)

    med = {k: statistics.median(v) for k, v in wall.items()}
    scipy_name = parts[-1][0]
    scipy = statistics.median(inner[scipy_name])
    lines = [
        f"# Parts of the {a.nodes}-node `simulate` process (bench/process_parts.py)", "",
        f"Command: `bench/process_parts.py --thermnet {a.thermnet} --nodes {a.nodes} --repeat {a.repeat}`",
        "", f"Generated {time.strftime('%Y-%m-%d %H:%M', time.gmtime())} UTC; plate {rows} x {cols} "
        f"(bench/plate.py), {dur:g} s transient. Medians (and ranges) over {a.repeat} interleaved "
        "rounds; wall and CPU (user + system) of the whole process from GNU time; solve = the "
        "integration's own wall time (thermnet `--stats`, SciPy `solve_ivp`).", "",
        "| part | wall s | range s | CPU s | solve s | process − solve s | process / SciPy solve |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, _, solve in parts:
        w = med[name]
        s = statistics.median(inner[name]) if solve else None
        rng = f"{min(wall[name]):.3f}-{max(wall[name]):.3f}"
        cells = [name, f"{w:.3f}", rng, f"{statistics.median(cpu[name]):.3f}",
                 f"{s:.3f}" if s is not None else "–",
                 f"{w - s:.3f}" if s is not None and name != scipy_name else "–",
                 f"{w / scipy:.3f}" if name != scipy_name else "–"]
        lines.append("| " + " | ".join(cells) + " |")
    whole = med["whole, rtol = atol = 1e-5"]
    lines += ["", f"Ratio at bench/run.py's matched accuracy: whole thermnet process {whole:.3f} s / "
              f"SciPy solve {scipy:.3f} s = **{whole / scipy:.3f}** (goal 0.1)."]
    text = "\n".join(lines) + "\n"
    print(text)
    if a.results:
        d = os.path.dirname(os.path.abspath(a.results))
        with tempfile.NamedTemporaryFile("w", dir=d, delete=False, suffix=".tmp") as f:
            f.write(text)
        os.replace(f.name, a.results)


if __name__ == "__main__":
    main()
