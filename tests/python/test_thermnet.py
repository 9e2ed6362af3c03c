#!/usr/bin/env python3
"""The thermnet Python module: every call, its errors, the GIL release, and results identical to
the `thermnet` command line's for the same model (CSV digits and JSON reports)."""

import csv
import json
import os
import re
import shutil
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
INCUBATOR = os.path.join(SRC, "models", "incubator", "incubator.tnet")
HOUSE = os.path.join(SRC, "models", "armadillo", "house_2r2c.tnet")

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
        with self.assertRaisesRegex(ValueError, "no node, boundary or sensor 'lens9'"):
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


def read_columns(path, names):
    """Columns of a CSV file as floats (on/off words as 1/0), by name."""
    words = {"true": 1.0, "false": 0.0}

    def value(cell):
        word = cell.strip().lower()
        return words[word] if word in words else float(cell)

    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    return {n: np.array([value(r[n]) for r in rows]) for n in names}


def lagged(times, values, tau):
    """An independent first-order lag dR/dt = (T - R)/tau of a series taken as linear between its
    samples (exact for such a series), starting in equilibrium."""
    out = [values[0]]
    for k in range(1, len(times)):
        h = times[k] - times[k - 1]
        slope = (values[k] - values[k - 1]) / h
        decay = np.exp(-h / tau)
        out.append(values[k] - tau * slope + (out[-1] - values[k - 1] + tau * slope) * decay)
    return np.array(out)


def incubator_by_hand(rows, on, room, t_air0, times, C=600.0, G=0.5, P=11.42 * 1.427):
    """The published 2-parameter incubator, C dT/dt = G (room - T) + P on(t), solved exactly
    between breakpoints: `on` held from each row to the next, `room` linear between rows and
    constant after the last (as thermnet's held and linear tables are)."""
    a = G / C
    marks = np.union1d(rows, times)
    marks = marks[(marks >= 0) & (marks <= times[-1])]
    temp, out = t_air0, {0.0: t_air0}
    for u, v in zip(marks[:-1], marks[1:]):
        k = max(0, np.searchsorted(rows, u, side="right") - 1)
        r0 = np.interp(u, rows, room)
        slope = (room[k + 1] - room[k]) / (rows[k + 1] - rows[k]) if u < rows[-1] else 0.0
        # T(t) = Tp(t) + (T(u) - Tp(u)) exp(-a (t - u)) with Tp = r0 + s (t - u) - s/a + P on/(a C)
        tp = lambda t: r0 + slope * (t - u) - slope / a + P * on[k] / (a * C)
        temp = tp(v) + (temp - tp(u)) * np.exp(-a * (v - u))
        out[float(v)] = temp
    return np.array([out[float(t)] for t in times])


class CampaignTest(unittest.TestCase):
    """The published models of recorded campaigns (issue 28): the incubator and the Armadillo Box
    read their CSV files as published (UNIX time stamps, True/False heater, a column map with the
    mean of two sensors, `Time` and `xi`), simulate, read sensors and calibrate like the CLI."""

    def test_incubator_loads_and_simulates_from_the_published_files(self):
        m = thermnet.Model.load(INCUBATOR)
        self.assertEqual(m.cases, ["random_on_off", "ramp", "lid_opening"])
        self.assertEqual(m.nodes, ["room", "air"])
        self.assertEqual(set(m.params), {"C_air", "G_box"})
        r = m.simulate(case="random_on_off")
        self.assertEqual(r.times[0], 0.0)
        self.assertEqual(r.times[-1], 4585.0)
        data = read_columns(os.path.join(SRC, "models", "incubator", "random_on_off_sequences_1.csv"),
                            ["time", "t1", "t2", "t3", "heater_on"])
        air, room = r.nodes.index("air"), r.nodes.index("room")
        # initial = data: the air starts at the mean of its two sensors' first readings, and the
        # room follows the file's t1 (a boundary read from the case's own file).
        self.assertAlmostEqual(r.temperatures[0, air], (data["t2"][0] + data["t3"][0]) / 2, places=9)
        elapsed = data["time"] - data["time"][0]
        np.testing.assert_allclose(r.temperatures[:, room], np.interp(r.times, elapsed, data["t1"]),
                                   atol=1e-9)
        # The whole run against the model's equation solved exactly by hand: the lamp held on
        # and off as the file's True/False column says, the room linear between rows. (The
        # difference shrinks with the tolerances: 4.5e-3 K at 1e-6, 6e-4 K at 1e-8, 1e-5 K at
        # 1e-10.)
        fine = m.simulate(case="random_on_off", rtol=1e-8, atol=1e-8)
        by_hand = incubator_by_hand(elapsed, data["heater_on"], data["t1"],
                                    fine.temperatures[0, air], fine.times)
        np.testing.assert_allclose(fine.temperatures[:, air], by_hand, atol=2e-3)
        self.assertGreater(np.ptp(by_hand), 0.5)  # the lamp's switching moves the air
        out = cli("simulate", INCUBATOR, "--case", "random_on_off")
        rows = list(csv.reader(out.splitlines()))
        self.assertEqual(rows[0][1:], r.nodes)
        self.assertEqual(len(rows) - 1, len(r.times))
        self.assertEqual(rows[-1][1:], same_digits(rows[-1][1:], r.temperatures[-1]))

    def test_sensor_readings_as_the_cli_prints_them(self):
        with tempfile.TemporaryDirectory() as tmp:
            for name in ("random_on_off_sequences_1.csv", "ramp_up_cool_down.csv",
                         "lid_opening_experiment_jan_2021.csv"):
                shutil.copy(os.path.join(SRC, "models", "incubator", name), tmp)
            with open(INCUBATOR, encoding="utf-8") as f:
                text = f.read().replace("node air C = C_air",
                                        "node air C = C_air\nsensor probe air tau = 35 [s] offset = 0.4")
            path = os.path.join(tmp, "probe.tnet")
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
            m = thermnet.Model.load(path)
            r = m.simulate(case="ramp", output=1, sensors=True)
            self.assertEqual(r.nodes, ["room", "air", "probe"])
            rows = list(csv.reader(cli("simulate", path, "--case", "ramp", "--output", "1",
                                       "--sensors").splitlines()))
            self.assertEqual(rows[0][1:], r.nodes)
            for k in (0, 1000, len(rows) - 2):
                self.assertEqual(rows[k + 1][1:], same_digits(rows[k + 1][1:], r.temperatures[k]))
            # The reading is offset + the air lagged by 35 s (an independent integration of the
            # simulated air temperature, exact for an air temperature linear between seconds).
            air, probe = r.temperatures[:, 1], r.temperatures[:, 2]
            np.testing.assert_allclose(probe, 0.4 + lagged(r.times, air, 35.0), atol=0.01)
            self.assertGreater(np.abs(probe - 0.4 - air).max(), 0.2)  # the lag is visible
            only = m.simulate(case="ramp", output=1, sensors=True, nodes=["probe"])
            np.testing.assert_array_equal(only.temperatures[:, 0], probe)
            without = m.simulate(case="ramp", output=1)
            self.assertEqual(without.nodes, ["room", "air"])
            with self.assertRaisesRegex(ValueError, "no node, boundary or sensor 'probe'"):
                m.simulate(case="ramp", nodes=["probe"])

    def test_house_simulates_with_a_start_temperature_fitted_per_case(self):
        m = thermnet.Model.load(HOUSE)
        self.assertEqual(m.cases, ["sequence"])
        te0 = m.params["Te.T0@sequence"]
        self.assertAlmostEqual(te0["value"], 293.15)  # 20 degC, SI
        self.assertEqual((te0["lo"], te0["hi"]), (278.15, 313.15))
        r = m.simulate()
        self.assertAlmostEqual(r.times[-1], 89.5 * 3600)
        data = read_columns(os.path.join(SRC, "models", "armadillo", "statespace.csv"), ["Time", "xi"])
        ti, te = r.nodes.index("Ti"), r.nodes.index("Te")
        self.assertAlmostEqual(r.temperatures[0, ti], data["xi"][0], places=9)  # initial = data
        self.assertAlmostEqual(r.temperatures[0, te], 20.0, places=9)
        warmer = m.simulate(params={"Te.T0@sequence": 303.15})
        self.assertAlmostEqual(warmer.temperatures[0, te], 30.0, places=9)

    def test_house_calibrates_like_the_cli(self):
        m = thermnet.Model.load(HOUSE)
        py = m.calibrate(method="lm")
        self.assertLessEqual(py["rmse"], 0.13)
        self.assertEqual(without_wall(py), without_wall(cli_json("calibrate", HOUSE, "--method", "lm")))
        self.assertIn("Te.T0@sequence", py["params"])
        # The fitted params, passed back as they are, reproduce the fit's residual.
        fitted = m.simulate(params=py["params"])
        data = read_columns(os.path.join(SRC, "models", "armadillo", "statespace.csv"), ["Time", "xi"])
        ti = np.interp(data["Time"], fitted.times, fitted.temperatures[:, fitted.nodes.index("Ti")])
        self.assertAlmostEqual(float(np.sqrt(np.mean((ti - data["xi"]) ** 2))), py["rmse"], delta=0.01)


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
