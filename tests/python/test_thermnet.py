#!/usr/bin/env python3
"""The thermnet Python module: every call, its errors, the GIL release, and results identical to
the `thermnet` command line's for the same model (CSV digits and JSON reports)."""

import csv
import json
import os
import re
import subprocess
import sys
import tempfile
import threading
import unittest

import numpy as np

import thermnet

EXE = os.environ["THERMNET_EXE"]
SRC = os.environ["THERMNET_SOURCE_DIR"]
CAMERA = os.path.join(SRC, "models", "aerial_camera", "camera.tnet")

TWO_PLATES = """model two_plates
param h_gap = 4 [W/(m^2*K)] range 1 .. 10 "gas gap convection"
boundary ambient T = pwl(0: 20, 2750: -35)
node plate1 C = 450 [J/K]
node plate2 C = 300 [J/K] T0 = 20
convection gap plate1 plate2 h = h_gap A = 0.02
conduction mount plate2 ambient k = 0.25 L = 3 [mm] A = 54.8 [mm^2]
heater film plate1 P = 10
case warmup {
  duration = 3 [h]
  film.P = step(0: 10, 2500: 0)
}
case cold { duration = 1 [h] }
"""


def cli(*args):
    """Runs the command line; returns its standard output (fails the test on a non-zero exit)."""
    done = subprocess.run([EXE, *args], capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise AssertionError(f"thermnet {' '.join(args)} exited {done.returncode}: {done.stderr}")
    return done.stdout


def cli_json(*args):
    """Runs a command with --json and returns the report."""
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "report.json")
        cli(*args, "--json", path)
        with open(path, encoding="utf-8") as f:
            return json.load(f)


def same_digits(cells, values):
    """The values printed with as many decimals as the CLI's CSV cells carry."""
    decimals = len(cells[0].split(".")[1])
    return [f"{v:.{decimals}f}" for v in values]


def without_wall(report):
    """A report without its wall-clock time, the one field two runs may not share."""
    return {k: v for k, v in report.items() if k != "wall_s"}


class LoadingTest(unittest.TestCase):
    def test_load_lists_nodes_params_cases(self):
        m = thermnet.Model.load(CAMERA)
        self.assertEqual(len(m.nodes), 24)
        self.assertEqual(m.cases, [f"case{i:02d}" for i in range(1, 12)])
        self.assertEqual(m.name, "aerial_camera")
        k2 = m.params["k2"]
        self.assertEqual((k2["value"], k2["lo"], k2["hi"]), (160.0, 80.0, 180.0))
        self.assertEqual(k2["doc"], "conductivity of frame")

    def test_from_string(self):
        m = thermnet.Model.from_string(TWO_PLATES, name="two_plates.tnet")
        self.assertEqual(m.nodes, ["ambient", "plate1", "plate2"])
        self.assertEqual(m.cases, ["warmup", "cold"])
        self.assertEqual(m.params["h_gap"]["value"], 4.0)
        plain = thermnet.Model.from_string("model b\nnode a C = 1 [J/K]\n")
        self.assertEqual((plain.nodes, plain.params, plain.cases), (["a"], {}, []))

    def test_error_carries_file_line_column(self):
        text = "model bad\nnode a C = 1 [J/K]\nconvection c a b h = 1 A = 1\n"
        with self.assertRaises(thermnet.ModelError) as ctx:
            thermnet.Model.from_string(text, name="bad.tnet")
        e = ctx.exception
        self.assertEqual((e.file, e.line, e.column), ("bad.tnet", 3, 1))
        self.assertIn("bad.tnet:3:1: error: unknown node 'b'", str(e))
        self.assertIsInstance(e, ValueError)

    def test_syntax_error_in_a_file(self):
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "broken.tnet")
            with open(path, "w", encoding="utf-8") as f:
                f.write("model broken\nnode a C = = 1\n")
            with self.assertRaises(thermnet.ModelError) as ctx:
                thermnet.Model.load(path)
            self.assertEqual((ctx.exception.file, ctx.exception.line), (path, 2))
            self.assertGreater(ctx.exception.column, 1)

    def test_missing_file(self):
        with self.assertRaises(thermnet.ModelError) as ctx:
            thermnet.Model.load("/nonexistent/model.tnet")
        self.assertEqual(ctx.exception.file, "/nonexistent/model.tnet")
        self.assertEqual(ctx.exception.line, 0)

    def test_bad_plugin(self):
        with self.assertRaises(RuntimeError) as ctx:
            thermnet.load_plugin("/nonexistent/libnothing.so")
        self.assertIn("cannot load plugin", str(ctx.exception))


class SimulateTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.model = thermnet.Model.load(CAMERA)

    def test_identical_to_cli_csv(self):
        r = self.model.simulate(case="case03", params={"k7": 12.5})
        out = cli("simulate", CAMERA, "--case", "case03", "--set", "k7=12.5")
        rows = list(csv.reader(out.splitlines()))
        self.assertEqual(rows[0][1:], r.nodes)
        self.assertEqual(len(rows) - 1, len(r.times))
        for k, row in enumerate(rows[1:]):
            self.assertEqual(float(row[0]), r.times[k])
            self.assertEqual(row[1:], same_digits(row[1:], r.temperatures[k]))
        # The override had an effect: the nominal run differs.
        self.assertFalse(np.array_equal(r.temperatures, self.model.simulate(case="case03").temperatures))

    def test_nodes_durations_and_numpy_shapes(self):
        r = self.model.simulate(case="case01", nodes=["lens1_c", "win_c"], duration=600, output=60)
        self.assertEqual(r.nodes, ["lens1_c", "win_c"])
        np.testing.assert_array_equal(r.times, np.arange(0, 601, 60, dtype=float))
        self.assertEqual(r.temperatures.shape, (11, 2))
        self.assertEqual(r.temperatures.dtype, np.float64)
        full = self.model.simulate(case="case01", duration=600, output=60)
        col = full.nodes.index("win_c")
        np.testing.assert_array_equal(r.temperatures[:, 1], full.temperatures[:, col])
        self.assertAlmostEqual(r.temperatures[0, 0], -38.5, places=9)  # `initial = -38.5`

    def test_to_pandas(self):
        df = self.model.simulate(case="case01", nodes=["lens1_c"], duration=300, output=60).to_pandas()
        self.assertEqual(list(df.columns), ["lens1_c"])
        self.assertEqual(df.index.name, "time")
        self.assertEqual(list(df.index), [0.0, 60.0, 120.0, 180.0, 240.0, 300.0])

    def test_steady_matches_cli(self):
        m = thermnet.Model.from_string(TWO_PLATES, name="two_plates.tnet")
        r = m.steady(case="cold")
        self.assertEqual(list(r.times), [0.0])
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "two_plates.tnet")
            with open(path, "w") as f:
                f.write(TWO_PLATES)
            rows = list(csv.reader(cli("simulate", path, "--case", "cold", "--steady").splitlines()))
        self.assertEqual(rows[1][1:], same_digits(rows[1][1:], r.temperatures[0]))
        # Energy balance at steady state: the plates sit where 10 W leave through the mount.
        plate2 = r.temperatures[0, r.nodes.index("plate2")]
        g_mount = 0.25 * 54.8e-6 / 3e-3
        self.assertAlmostEqual((plate2 - 20.0) * g_mount, 10.0, places=6)

    def test_errors(self):
        with self.assertRaises(thermnet.ModelError) as ctx:
            self.model.simulate(case="case99")
        self.assertIn("case99", str(ctx.exception))
        with self.assertRaisesRegex(ValueError, "no param 'k77'; did you mean 'k7'"):
            self.model.simulate(case="case01", params={"k77": 1.0})
        with self.assertRaisesRegex(ValueError, "no node or boundary 'lens9'"):
            self.model.simulate(case="case01", nodes=["lens9"])
        with self.assertRaises(TypeError):
            self.model.simulate(case="case01", params={"k7": "high"})

    def test_values_the_command_line_refuses_are_refused(self):
        # The same rules as `thermnet simulate` (its --rtol/--atol/--duration and --set), checked
        # by the same code: each message is the command line's.
        m = thermnet.Model.from_string(TWO_PLATES, name="two_plates.tnet")
        for kwargs, message in [
                ({"atol": float("inf")}, r"atol = inf is not a number from 1e-12 to 10 K"),
                ({"rtol": 10}, r"rtol = 10 is not a number from 1e-12 to 0.1"),
                ({"rtol": float("nan")}, r"rtol = nan is not"),
                ({"duration": -5}, r"duration = -5 is not a positive number"),
                ({"output": 0}, r"output = 0 is not a positive number"),
                ({"params": {"h_gap": 20}},
                 r"param 'h_gap' = 20 W/\(m\^2\*K\) lies outside its range 1 W/\(m\^2\*K\) \.\. 10"),
                ({"params": {"h_gap": float("nan")}}, r"param 'h_gap' must be a finite number"),
                ({"params": {"mount.k": -1}}, r"'mount.k' \('k' of 'mount'\) must be > 0"),
                ({"params": {"plate1.T0": -5}}, r"must be above absolute zero")]:
            with self.subTest(kwargs=kwargs), self.assertRaisesRegex(ValueError, message):
                m.simulate(case="cold", **kwargs)
        with self.assertRaisesRegex(ValueError, r"tolerance = -1 is not a positive number"):
            m.calibrate(tolerance=-1)
        with self.assertRaisesRegex(ValueError, r"threads = -2 is not a non-negative whole"):
            m.sensitivity(threads=-2)
        with self.assertRaisesRegex(ValueError, r"case 'cold' is given twice"):
            m.diagnose(cases=["cold", "cold"])

    def test_keys_are_set_like_the_command_line_set(self):
        # params={"OBJECT.KEY": SI value} is `--set OBJECT.KEY=...`: the same rows.
        m = thermnet.Model.from_string(TWO_PLATES, name="two_plates.tnet")
        r = m.simulate(case="cold", params={"film.P": 4.0}, duration=600, output=60)
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "two_plates.tnet")
            with open(path, "w") as f:
                f.write(TWO_PLATES)
            rows = list(csv.reader(cli("simulate", path, "--case", "cold", "--set", "film.P=4",
                                       "--duration", "600", "--output", "60").splitlines()))
        self.assertEqual(len(rows) - 1, len(r.times))
        for k, row in enumerate(rows[1:]):
            self.assertEqual(row[1:], same_digits(row[1:], r.temperatures[k]))
        nominal = m.simulate(case="cold", duration=600, output=60)
        self.assertFalse(np.array_equal(r.temperatures, nominal.temperatures))


class GilTest(unittest.TestCase):
    def test_two_threads_solve_at_once_with_equal_results(self):
        m = thermnet.Model.load(CAMERA)
        serial = [m.simulate(case=c).temperatures for c in ("case02", "case05")]
        results = {}

        def run(c):
            results[c] = m.simulate(case=c).temperatures

        threads = [threading.Thread(target=run, args=(c,)) for c in ("case02", "case05")]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        np.testing.assert_array_equal(results["case02"], serial[0])
        np.testing.assert_array_equal(results["case05"], serial[1])

    def test_python_runs_while_a_solve_is_under_way(self):
        # With a switch interval of 1000 s no thread is preempted: the main thread can run while
        # the worker is inside calibrate() only if calibrate() released the GIL.
        m = thermnet.Model.load(CAMERA)
        entered, state = threading.Event(), {"solved": False}

        def work():
            entered.set()
            m.calibrate(method="mc", samples=40, cases=["case01"], threads=1)
            state["solved"] = True

        old = sys.getswitchinterval()
        sys.setswitchinterval(1000)
        try:
            t = threading.Thread(target=work)
            t.start()
            entered.wait()
            ran_during_solve = not state["solved"]
            t.join()
        finally:
            sys.setswitchinterval(old)
        self.assertTrue(ran_during_solve)
        self.assertTrue(state["solved"])


class ReportsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.model = thermnet.Model.load(CAMERA)

    def test_calibrate_lm_equals_cli_json(self):
        py = self.model.calibrate(method="lm", cases=["case01"])
        cl = cli_json("calibrate", CAMERA, "--method", "lm", "--case", "case01")
        self.assertEqual(without_wall(py), without_wall(cl))
        self.assertEqual(py["method"], "lm")
        self.assertLess(py["rmse"], 1.0)

    def test_calibrate_mc_equals_cli_json(self):
        py = self.model.calibrate(method="mc", samples=60, seed=7, tolerance=4, cases=["case01"])
        cl = cli_json("calibrate", CAMERA, "--method", "mc", "--samples", "60", "--seed", "7",
                      "--tolerance", "4", "--case", "case01")
        self.assertEqual(without_wall(py), without_wall(cl))
        self.assertEqual(py["samples"], 60)

    def test_sensitivity_equals_cli_json(self):
        py = self.model.sensitivity(cases=["case01"])
        self.assertEqual(py, cli_json("sensitivity", CAMERA, "--case", "case01"))
        self.assertEqual(sorted(py["ranking"]), sorted(self.model.params))

    def test_diagnose_equals_cli_json(self):
        py = self.model.diagnose(cases=["case01"], top=3)
        cl = cli_json("diagnose", CAMERA, "--case", "case01", "--top", "3")
        self.assertEqual(without_wall(py), without_wall(cl))
        self.assertIn("findings", py)

    def test_report_errors(self):
        with self.assertRaisesRegex(ValueError, "unknown method 'lmm'; did you mean 'lm'"):
            self.model.calibrate(method="lmm")
        plain = thermnet.Model.from_string("model p\nnode a C = 1 [J/K]\n", name="p.tnet")
        with self.assertRaisesRegex(ValueError, "no param has a range"):
            plain.calibrate()
        with self.assertRaises(thermnet.ModelError):
            self.model.calibrate(cases=["nope"])


class ExampleTest(unittest.TestCase):
    def test_notebook_example_improves_the_held_out_case(self):
        script = os.path.join(SRC, "python", "examples", "camera_calibration.py")
        with tempfile.TemporaryDirectory() as tmp:
            done = subprocess.run([sys.executable, script, tmp], capture_output=True, text=True,
                                  check=True)
            self.assertGreater(os.path.getsize(os.path.join(tmp, "camera_calibration.png")), 10000)
        nominal, fitted = map(float, re.search(r"RMSE nominal ([0-9.]+) K -> calibrated ([0-9.]+) K",
                                               done.stdout).groups())
        self.assertLess(fitted, nominal / 2)


if __name__ == "__main__":
    unittest.main()
