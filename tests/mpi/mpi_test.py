#!/usr/bin/env python3
"""thermnet under mpirun: calibrate (mc, lhs), simulate --samples, sweep and diagnose over 2 and 3
ranks give the single-process result bit for bit; a rank that fails or is killed mid-run ends the
whole job with a clear error within a time limit."""

import json
import os
import re
import signal
import subprocess
import tempfile
import time
import unittest
import uuid

EXE = os.environ["THERMNET_EXE"]
SRC = os.environ["THERMNET_SOURCE_DIR"]
MPIRUN = os.environ.get("MPIEXEC") or "mpirun"
CAMERA = os.path.join(SRC, "models", "aerial_camera", "camera.tnet")
SCENARIO = os.path.join(SRC, "tests", "diagnose_scenarios", "generate.py")
LIMIT = 300  # seconds: a run that takes longer is a hang
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")


def run(args, ranks, cwd):
    """Runs thermnet directly (ranks == 0) or under mpirun; returns the finished process."""
    cmd = [EXE, *args] if ranks == 0 else [MPIRUN, "-n", str(ranks), "--oversubscribe", EXE, *args]
    return subprocess.run(cmd, cwd=cwd, env=ENV, capture_output=True, text=True, timeout=LIMIT,
                          check=False)


def outputs(args, ranks):
    """The files a run writes into a fresh directory, by name, as bytes."""
    with tempfile.TemporaryDirectory() as tmp:
        done = run(args, ranks, tmp)
        if done.returncode != 0:
            raise AssertionError(f"{ranks} ranks: exit {done.returncode}: {done.stderr}")
        files = {}
        for name in sorted(os.listdir(tmp)):
            with open(os.path.join(tmp, name), "rb") as f:
                files[name] = f.read()
        return files, done


def without_wall(report_bytes):
    report = json.loads(report_bytes)
    report.pop("wall_s")
    return report


def wall_blanked(report_bytes):
    """A JSON report's bytes with the value of its wall time (which no two runs share) blanked."""
    blanked, count = re.subn(rb'"wall_s": [^,\n]+', b'"wall_s": -', report_bytes)
    if count != 1:
        raise AssertionError(f"{count} wall_s fields in the report")
    return blanked


class SameResultTest(unittest.TestCase):
    def check_calibration(self, method):
        args = ["calibrate", CAMERA, "--method", method, "--samples", "150", "--seed", "11",
                "--case", "case01", "--tolerance", "4", "--json", "r.json", "-o", "cal.tnet"]
        single, _ = outputs(args + ["--threads", "2"], 0)
        self.assertGreater(json.loads(single["r.json"])["accepted"], 0)
        for ranks in (2, 3):
            spread, done = outputs(args + ["--threads", "1"], ranks)
            self.assertEqual(sorted(spread), sorted(single))
            # The JSON report in full except the wall time, and the calibrated model bit for bit.
            self.assertEqual(without_wall(spread["r.json"]), without_wall(single["r.json"]))
            for name in single:
                if name != "r.json":
                    self.assertEqual(spread[name], single[name], name)
            # Only rank 0 prints the table.
            self.assertEqual(done.stdout.count("(param values in SI units)"), 1)

    def test_monte_carlo(self):
        self.check_calibration("mc")

    def test_latin_hypercube(self):
        self.check_calibration("lhs")

    def test_uncertainty_bands(self):
        args = ["simulate", CAMERA, "--case", "case02", "--samples", "25", "--seed", "5",
                "--percentiles", "10,50,90", "-o", "bands.csv"]
        single, _ = outputs(args, 0)
        for ranks in (2, 3):
            spread, _ = outputs(args + ["--threads", "1"], ranks)
            self.assertEqual(spread["bands.csv"], single["bands.csv"])


class SweepTest(unittest.TestCase):
    # A param without a range may take any value on the command line; a negative conductance then
    # fails at its grid point (the camera's params are ranged: out-of-range values are refused
    # before the grid runs).
    MODEL = """model bar
param G = 2 [W/K]
boundary amb T = 20
node a C = 100
node b C = 50 T0 = 60
conductance g1 a amb G = 1
conductance g2 a b G = G
heater h a P = 5
case c { duration = 600 ; output = 60 }
"""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.bar = os.path.join(cls.tmp.name, "bar.tnet")
        with open(cls.bar, "w") as f:
            f.write(cls.MODEL)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_sweep(self):
        # 3 x 2 grid points, every other one failing (a negative conductance): the error column
        # travels between ranks too. 3 ranks get 2 points each, 2 ranks 3 each.
        args = ["sweep", self.bar, "--param", "h.P=2..10:3", "--param", "G=-1,3", "--band",
                "25..40", "-o", "table.csv", "--plot", "sweep.svg"]
        single, done = outputs(args + ["--threads", "2"], 0)
        self.assertEqual(single["table.csv"].count(b"must be > 0"), 3)
        self.assertIn("6 runs, 3 failed", done.stderr)
        for ranks in (2, 3):
            spread, done = outputs(args + ["--threads", "1"], ranks)
            self.assertEqual(spread, single)
            self.assertEqual(done.stderr.count("6 runs, 3 failed"), 1)

    def test_sweep_table_on_standard_output(self):
        args = ["sweep", CAMERA, "--case", "case01", "--param", "k8=2..10:5", "--nodes", "lens1*"]
        _, single = outputs(args, 0)
        _, spread = outputs(args + ["--threads", "1"], 3)
        self.assertEqual(spread.stdout, single.stdout)
        self.assertEqual(len(single.stdout.splitlines()), 6)


class DiagnoseTest(unittest.TestCase):
    """Scenario D01 of the diagnosis scenarios (a 10-node bar, two cases, every ranged param off
    and two hidden effects): the shortlist's refits, the joint refit with the ranged params and a
    second forward-selection step all run spread over the ranks."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.model = os.path.join(cls.tmp.name, "model.tnet")
        subprocess.run(["/usr/bin/python3", SCENARIO, "D01", cls.tmp.name], check=True,
                       capture_output=True, timeout=LIMIT)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_diagnose(self):
        args = ["diagnose", self.model, "--json", "r.json", "--write", "ext.tnet", "--plot",
                "d.svg"]
        single, done = outputs(args + ["--threads", "2"], 0)
        report = json.loads(single["r.json"])
        self.assertEqual(len(report["findings"]), 2)  # a forward-selection step was taken
        self.assertIn("refitted jointly with the ranged params", single["r.json"].decode())
        for ranks in (2, 3):
            spread, spread_done = outputs(args + ["--threads", "1"], ranks)
            self.assertEqual(sorted(spread), sorted(single))
            # The text report and every file byte for byte (the JSON's wall time aside).
            self.assertEqual(spread_done.stdout, done.stdout)
            self.assertEqual(wall_blanked(spread["r.json"]), wall_blanked(single["r.json"]))
            for name in ("ext.tnet", "d.svg"):
                self.assertEqual(spread[name], single[name], name)

    def test_a_killed_rank_ends_the_diagnosis(self):
        # (the camera against all its cases: refits for a minute, far longer than the second
        # before the kill on any machine)
        err = run_and_kill_rank_1(["diagnose", CAMERA, "--threads", "1"])
        self.assertRegex(err, r"rank 1 .*(signal 9|Killed)|signal 9")


class FailureTest(unittest.TestCase):
    def test_a_failing_rank_ends_the_job(self):
        # Rank 0 runs a long calibration; rank 1 cannot read its model and stops at once: rank 0
        # must not wait for it forever.
        with tempfile.TemporaryDirectory() as tmp:
            cmd = [MPIRUN, "-n", "1", EXE, "calibrate", CAMERA, "--method", "mc", "--samples",
                   "100000", ":", "-n", "1", EXE, "calibrate", "/nonexistent/model.tnet",
                   "--method", "mc", "--samples", "100000"]
            start = time.monotonic()
            done = subprocess.run(cmd, cwd=tmp, env=ENV, capture_output=True, text=True,
                                  timeout=LIMIT, check=False)
        self.assertNotEqual(done.returncode, 0)
        self.assertIn("[rank 1] /nonexistent/model.tnet: error: cannot read file", done.stderr)
        self.assertIn("thermnet: rank 1 of 2 failed (exit status 2); ending the job", done.stderr)
        self.assertLess(time.monotonic() - start, LIMIT)

    def test_a_failing_rank_ends_a_sweep_or_diagnosis(self):
        # Rank 1 stops at once (a bad grid, a missing model) while rank 0 runs its share and
        # waits for rank 1's results.
        sweep = ["sweep", CAMERA, "--case", "case01", "--threads", "1", "--param"]
        for good, bad in (
                ([*sweep, "k7=2..15:40"], [*sweep, "k99=1,2"]),
                (["diagnose", CAMERA, "--case", "case03", "--threads", "1"],
                 ["diagnose", "/nonexistent/model.tnet", "--threads", "1"])):
            with self.subTest(good[0]), tempfile.TemporaryDirectory() as tmp:
                cmd = [MPIRUN, "-n", "1", EXE, *good, ":", "-n", "1", EXE, *bad]
                done = subprocess.run(cmd, cwd=tmp, env=ENV, capture_output=True, text=True,
                                      timeout=LIMIT, check=False)
                self.assertNotEqual(done.returncode, 0)
                self.assertRegex(done.stderr, r"\[rank 1\] .*(k99|/nonexistent/model.tnet)")
                self.assertRegex(done.stderr,
                                 r"thermnet: rank 1 of 2 failed \(exit status \d\); ending the job")

    def test_the_same_error_on_every_rank_is_printed_once(self):
        # Every rank reads the same bad model: the job ends with the error's status, printed once
        # (by rank 0), and no rank aborts the job (no MPI_Abort banner, no "[rank 1]" copy).
        with tempfile.TemporaryDirectory() as tmp:
            with open(os.path.join(tmp, "bad.tnet"), "w", encoding="utf-8") as f:
                f.write("boundary b T = 20\nnode n C = 1\nconductance g n b G = x\n")
            done = run(["simulate", "bad.tnet"], 2, tmp)
        self.assertEqual(done.returncode, 1, done.stderr)
        self.assertEqual(done.stderr.count("bad.tnet:3:1: error: unknown const or param 'x'"), 1,
                         done.stderr)
        self.assertNotIn("[rank 1]", done.stderr)
        self.assertNotIn("MPI_ABORT", done.stderr)

    def test_ctrl_c_writes_the_best_result_so_far(self):
        # Ctrl-C reaches mpirun, which passes it on to the ranks as SIGTERM: every rank stops
        # drawing samples, the samples drawn are gathered, rank 0 writes the best so far and says
        # so once, and the job ends with status 1. mpirun kills the ranks 1 s after its SIGTERM by
        # default; on a loaded machine that can be too short even for this one-node model, so the
        # test gives them 5 s (odls_base_sigkill_timeout, docs/cluster.md).
        model = ("boundary amb T = 20\nnode n C = 1000 T0 = 50\nparam G = 1 [W/K] range 0.2 .. 5\n"
                 "conductance g n amb G = G\ncase c { duration = 100; output = 10; data \"meas.csv\" }\n")
        with tempfile.TemporaryDirectory() as tmp:
            with open(os.path.join(tmp, "truth.tnet"), "w", encoding="utf-8") as f:
                f.write(model.replace("G = 1 [W/K]", "G = 2 [W/K]").replace(' data "meas.csv"', ""))
            with open(os.path.join(tmp, "cal.tnet"), "w", encoding="utf-8") as f:
                f.write(model)
            subprocess.run([EXE, "simulate", "truth.tnet", "-o", "meas.csv"], cwd=tmp, env=ENV,
                           check=True, timeout=LIMIT)
            token = uuid.uuid4().hex
            env = dict(ENV, THERMNET_MPI_TEST_TOKEN=token)
            proc = subprocess.Popen(
                [MPIRUN, "-n", "2", "--oversubscribe", "--mca", "odls_base_sigkill_timeout", "5",
                 "-x", "THERMNET_MPI_TEST_TOKEN", EXE, "calibrate", "cal.tnet", "--method", "mc",
                 "--samples", "3000000", "--threads", "1", "--tolerance", "100", "--json",
                 "report.json"],
                cwd=tmp, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            deadline = time.monotonic() + 60
            while rank_process(token, 1) is None and time.monotonic() < deadline:
                time.sleep(0.2)
            time.sleep(3.0)  # into the sampling
            proc.send_signal(signal.SIGINT)
            try:
                _, err = proc.communicate(timeout=LIMIT)
            except subprocess.TimeoutExpired:
                proc.kill()
                _, err = proc.communicate()
                raise AssertionError(f"the job hung after Ctrl-C; stderr: {err}") from None
            self.assertEqual(proc.returncode, 1, err)
            self.assertEqual(err.count("interrupted; best result so far written"), 1, err)
            self.assertNotIn("rank 0 writes", err)
            self.assertNotIn("MPI_ABORT", err)
            with open(os.path.join(tmp, "report.json"), encoding="utf-8") as f:
                report = json.load(f)
        self.assertTrue(report["found"] and report["cancelled"], report)
        self.assertLess(report["samples"], 3000000, report)

    def test_a_killed_rank_ends_the_job(self):
        err = run_and_kill_rank_1(["calibrate", CAMERA, "--method", "mc", "--samples", "100000",
                                   "--threads", "1"])
        self.assertRegex(err, r"rank 1 .*(signal 9|Killed)|signal 9")


def run_and_kill_rank_1(args):
    """Runs thermnet on 2 ranks, kills rank 1 a second into the run and returns the job's stderr;
    fails the test when the job does not end with a non-zero status within the time limit."""
    token = uuid.uuid4().hex
    env = dict(ENV, THERMNET_MPI_TEST_TOKEN=token)
    with tempfile.TemporaryDirectory() as tmp:
        proc = subprocess.Popen(
            [MPIRUN, "-n", "2", "--oversubscribe", "-x", "THERMNET_MPI_TEST_TOKEN", EXE, *args],
            cwd=tmp, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        victim = None
        deadline = time.monotonic() + 60
        while victim is None and time.monotonic() < deadline and proc.poll() is None:
            victim = rank_process(token, 1)
            time.sleep(0.2)
        if victim is None:
            proc.kill()
            proc.communicate()
            raise AssertionError("rank 1 never started")
        time.sleep(1.0)  # let it get into the run
        os.kill(victim, signal.SIGKILL)
        try:
            _, err = proc.communicate(timeout=LIMIT)
        except subprocess.TimeoutExpired:
            proc.kill()
            _, err = proc.communicate()
            raise AssertionError(f"the job hung after rank 1 was killed; stderr: {err}") from None
    if proc.returncode == 0:
        raise AssertionError("the job ended with status 0 after rank 1 was killed")
    return err


def rank_process(token, rank):
    """The pid of the thermnet process of a rank started with our token, or None."""
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open(f"/proc/{pid}/environ", "rb") as f:
                env = f.read().split(b"\0")
            with open(f"/proc/{pid}/comm", encoding="utf-8") as f:
                comm = f.read().strip()
        except OSError:
            continue
        if (comm == "thermnet" and f"THERMNET_MPI_TEST_TOKEN={token}".encode() in env
                and f"OMPI_COMM_WORLD_RANK={rank}".encode() in env):
            return int(pid)
    return None


if __name__ == "__main__":
    unittest.main()
