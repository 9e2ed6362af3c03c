"""The whole-process timing the benchmarks share: a command run under GNU time (/usr/bin/time -v)."""
import subprocess
import tempfile
import time
from typing import NamedTuple


class Timed(NamedTuple):
    rc: int          # exit status
    stdout: str
    stderr: str
    wall_s: float    # the process's wall time, s
    max_rss_mib: float  # peak resident set size, MiB (NaN if GNU time did not report it)
    cpu_s: float     # user + system CPU time of the process, s


def timed(cmd, cwd=None) -> Timed:
    """Runs cmd under /usr/bin/time -v; its report goes to a private temp file, never into the
    caller's directory."""
    with tempfile.NamedTemporaryFile("r", suffix=".time.txt") as tf:
        t0 = time.perf_counter()
        p = subprocess.run(["/usr/bin/time", "-v", "-o", tf.name] + cmd, cwd=cwd,
                           capture_output=True, text=True)
        wall = time.perf_counter() - t0
        rss, cpu = float("nan"), 0.0
        for line in tf:
            key, _, value = line.strip().rpartition(": ")
            if key == "Maximum resident set size (kbytes)":
                rss = int(value) / 1024.0
            elif key in ("User time (seconds)", "System time (seconds)"):
                cpu += float(value)
    return Timed(p.returncode, p.stdout, p.stderr, wall, rss, cpu)
