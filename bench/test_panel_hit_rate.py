#!/usr/bin/python3
"""bench/panel_hit_rate.py's generator and scorer, without a long diagnosis (issue 55).

Usage: test_panel_hit_rate.py THERMNET   (thermnet is only linted with; the study's loop runs on a
stand-in binary that writes hand-made reports). The instances are built with 3 h cases at 60 s
instead of the study's 8 h at 30 s (the same draws otherwise), to keep the SciPy work short.
"""
import atexit
import os
import shutil
import subprocess
import sys
import tempfile
import textwrap
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import panel_hit_rate as ph  # noqa: E402
from network import num  # noqa: E402  (tests/diagnose_scenarios, on the path panel_hit_rate sets)

THERMNET = None
SEED = 7100
SHORT = (3.0, 60.0)  # hours, output s
LINK_KINDS = ("conductance", "convection", "contact", "conduction", "radiation")

_cache = {}


def instance(index: int, seed: int):
    """The scenario of (index, seed) at the short timing, and its folder with the written files."""
    if (index, seed) not in _cache:
        s = ph.build(index, seed, *SHORT)
        folder = tempfile.mkdtemp(prefix=f"panel_test_{index}_")
        atexit.register(shutil.rmtree, folder, True)
        truth = ph.gen.write(s, folder)
        with open(os.path.join(folder, "instance.txt"), "w") as f:
            f.write(ph.fingerprint(index, seed, *SHORT) + "\n")
        _cache[(index, seed)] = (s, folder, truth)
    return _cache[(index, seed)]


def model_links(path: str) -> list[set]:
    """The terminal pairs of every link declared in a .tnet model."""
    out = []
    with open(path) as f:
        for line in f:
            tok = line.split()
            if tok and tok[0] in LINK_KINDS:
                out.append({tok[2], tok[3]})
    return out


def model_heaters(path: str) -> dict[str, str]:
    with open(path) as f:
        return {t[1]: t[2] for t in (line.split() for line in f) if t and t[0] == "heater"}


class Generator(unittest.TestCase):
    def test_same_seed_same_instance(self):
        s, folder, _ = instance(0, SEED)
        again = ph.build(0, SEED, *SHORT)
        self.assertEqual(ph.gen.data_checksum(s), ph.gen.data_checksum(again))
        other = tempfile.mkdtemp(prefix="panel_test_again_")
        atexit.register(shutil.rmtree, other, True)
        ph.gen.write(again, other)
        for name in ("model.tnet", "truth.json", "run1.csv", "run3.csv"):
            with open(os.path.join(folder, name)) as a, open(os.path.join(other, name)) as b:
                self.assertEqual(a.read(), b.read(), name)

    def test_a_kept_instance_is_reused_only_when_it_is_the_same(self):
        _, folder, truth = instance(0, SEED)
        model = os.path.join(folder, "model.tnet")
        mtime = os.stat(model).st_mtime_ns
        self.assertEqual(ph.generated(folder, 0, SEED, *SHORT), truth)
        self.assertEqual(os.stat(model).st_mtime_ns, mtime)  # not written again
        self.assertNotEqual(ph.fingerprint(0, SEED, *SHORT), ph.fingerprint(0, SEED + 1, *SHORT))
        self.assertNotEqual(ph.fingerprint(0, SEED, *SHORT), ph.fingerprint(0, SEED, 8.0, 30.0))

    def test_another_seed_another_instance(self):
        s, _, _ = instance(0, SEED)
        self.assertNotEqual(ph.gen.data_checksum(s), ph.gen.data_checksum(instance(3, SEED + 3)[0]))

    def test_shape(self):
        s, _, truth = instance(0, SEED)
        self.assertEqual(len(s.net.nodes), 72)
        self.assertEqual(len(s.net.cases), 3)
        self.assertEqual(len(s.measured), 40)
        boxes = [h.node for h in s.net.heaters]
        self.assertEqual(sorted(boxes), [f"u{k}" for k in range(1, 7)])
        radiating = {lk.a for lk in s.net.links if lk.kind == "radiation" and lk.b == "shroud"}
        self.assertEqual(radiating, {n.name for n in s.net.nodes})  # every node radiates
        self.assertEqual(truth["nodes"], 72)

    def test_kinds_by_turn_and_lint(self):
        for i, kind in enumerate(ph.KINDS):
            s, folder, truth = instance(i, SEED + i)
            self.assertEqual([e["kind"] for e in truth["effects"]], [kind])
            r = subprocess.run([THERMNET, "lint", "model.tnet"], cwd=folder, capture_output=True, text=True)
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)

    def test_effect_absent_from_model_present_in_truth(self):
        for i in range(len(ph.KINDS)):
            s, folder, truth = instance(i, SEED + i)
            e = s.effects[0]
            model = os.path.join(folder, "model.tnet")
            with open(model) as f:
                self.assertNotIn("hidden", f.read())
            # seen above the 0.3 K noise: the effect alone moves a measured reading by > 3 sigma
            self.assertGreater(e.impact, 0.9)
            self.assertGreater(max(abs(d - c).max() for d, c in zip(s.clean, ph.gen._readings(
                s.net, s.params, [], s.measured)[0])), 0.9)
            if e.kind == "missing_link":
                boxes = {h.node for h in s.net.heaters}
                self.assertTrue(set(e.nodes) <= boxes, e.nodes)
                self.assertNotIn(set(e.nodes), model_links(model))
                self.assertTrue(s.truth_net.linked(*e.nodes))
                self.assertEqual(truth["effects"][0]["values"], {"G": e.strength})
            elif e.kind == "missing_source":
                self.assertEqual(sorted(model_heaters(model).values()), [f"u{k}" for k in range(1, 7)])
                added = [h for h in s.truth_net.heaters if h.name not in model_heaters(model)]
                self.assertEqual([h.node for h in added], e.nodes)
                self.assertTrue(all(c.heater_P[added[0].name].at(0.0) == s.effects[0].sign * e.strength
                                    for c in s.truth_net.cases))
            else:
                a = e.nodes[0]
                ratio = s.truth_net.node(a).C / s.net.node(a).C
                self.assertAlmostEqual(ratio, truth["effects"][0]["values"]["factor"], delta=1e-3 * ratio)
                self.assertGreater(abs(ratio - 1.0), 0.2)
                with open(model) as f:
                    line = next(x for x in f if x.startswith(f"node {a} "))
                self.assertIn(f"C = {num(s.net.node(a).C)} [J/K]", line)


def finding(kind, nodes, candidates=None, mechanism=None):
    f = {"kind": kind, "nodes": list(nodes), "values": {}}
    if mechanism:
        f["mechanism"] = mechanism
    if candidates is not None:
        f["candidates"] = [dict(f)] + candidates  # the finding itself first, as the JSON has it
    return f


def report(*findings):
    return {"baseline": {"rmse": 1.0}, "findings": list(findings)}


LINK_TRUTH = {"effects": [{"kind": "missing_link", "nodes": ["u2", "u5"], "mechanism": "linear", "element": None,
                           "values": {"G": 0.3}, "impact_K": 3.0, "measured": True}],
              "measured": ["u2", "u5"], "constant_heaters": []}
CAP_TRUTH = {"effects": [{"kind": "capacity_error", "nodes": ["p2_3"], "mechanism": None, "element": None,
                          "values": {"factor": 2.0}, "impact_K": 3.0, "measured": False}],
             "measured": [], "constant_heaters": []}


class Scorer(unittest.TestCase):
    def test_hit(self):
        self.assertEqual(ph.verdict(report(finding("missing_link", ["u2", "u5"])), LINK_TRUTH)[0], "hit")
        self.assertEqual(ph.verdict(report(finding("capacity_error", ["p2_3"])), CAP_TRUTH)[0], "hit")

    def test_link_pair_in_reverse_order_and_other_mechanism(self):
        self.assertEqual(ph.verdict(report(finding("missing_link", ["u5", "u2"])), LINK_TRUTH)[0], "hit")
        self.assertEqual(ph.verdict(report(finding("missing_link", ["u5", "u2"], mechanism="radiation")),
                                    LINK_TRUTH)[0], "hit")

    def test_parameter_findings_are_skipped(self):
        self.assertEqual(ph.verdict(report(finding("parameter", []), finding("missing_link", ["u2", "u5"])),
                                    LINK_TRUTH)[0], "hit")

    def test_ambiguous_via_rivals(self):
        f = finding("missing_link", ["u2", "u4"], candidates=[finding("missing_source", ["u2"]),
                                                              finding("missing_link", ["u5", "u2"])])
        v, text = ph.verdict(report(f), LINK_TRUTH)
        self.assertEqual(v, "ambiguous")
        self.assertIn("u2, u4", text)
        self.assertIn("+2 rivals", text)

    def test_miss(self):
        self.assertEqual(ph.verdict(report(finding("missing_link", ["u2", "u4"])), LINK_TRUTH)[0], "miss")
        self.assertEqual(ph.verdict(report(finding("missing_source", ["u2"])), LINK_TRUTH)[0], "miss")
        self.assertEqual(ph.verdict(report(finding("capacity_error", ["p2_4"])), CAP_TRUTH)[0], "miss")
        # the cause as the SECOND finding is a miss: only the first counts
        self.assertEqual(ph.verdict(report(finding("missing_source", ["p2_3"]), finding("capacity_error", ["p2_3"])),
                                    CAP_TRUTH)[0], "miss")
        # a rival beyond score.py's MAX_SET members does not count
        pad = [finding("missing_source", [f"p1_{k}"]) for k in range(1, 6)] + [finding("capacity_error", ["p2_3"])]
        self.assertEqual(ph.verdict(report(finding("missing_source", ["p9_9"], candidates=pad)), CAP_TRUTH)[0], "miss")

    def test_empty(self):
        self.assertEqual(ph.verdict(report(), LINK_TRUTH), ("miss", "none"))
        self.assertEqual(ph.verdict(report(finding("parameter", [])), LINK_TRUTH), ("miss", "none"))
        self.assertEqual(ph.verdict(None, LINK_TRUTH)[0], "error")

    def test_clopper_pearson(self):
        lo, hi = ph.clopper_pearson(0, 3)
        self.assertEqual(lo, 0.0)
        self.assertAlmostEqual(hi, 1 - 0.025 ** (1 / 3), places=6)
        lo, hi = ph.clopper_pearson(20, 20)
        self.assertAlmostEqual(lo, 0.025 ** (1 / 20), places=6)
        self.assertEqual(hi, 1.0)
        lo, hi = ph.clopper_pearson(10, 20)  # symmetric about one half
        self.assertAlmostEqual(lo + hi, 1.0, places=9)
        self.assertLess(lo, 0.5)


FAKE = textwrap.dedent("""\
    #!/usr/bin/python3
    # A stand-in for thermnet diagnose: P00 names the hidden effect with its pair reversed, P01 hangs.
    import json, os, sys, time
    here = os.path.basename(os.getcwd())
    if here == "P01":
        time.sleep(60)
    t = json.load(open("truth.json"))
    e = t["effects"][0]
    f = {"kind": e["kind"], "nodes": list(reversed(e["nodes"])), "values": {}}
    json.dump({"baseline": {"rmse": 1.0}, "findings": [f]}, open(sys.argv[sys.argv.index("--json") + 1], "w"))
    sys.stderr.write("  refits 1: 17 on 0 findings: 345 simulations, 1.0 s wall, 1.0 s CPU\\n"
                     "  refits 2: 3 jointly with the ranged params on 1 finding: 55 simulations, 1.0 s wall\\n")
    """)


class Study(unittest.TestCase):
    def test_loop_on_a_stand_in(self):
        with tempfile.TemporaryDirectory() as tmp:
            fake = os.path.join(tmp, "fake_thermnet")
            with open(fake, "w") as f:
                f.write(FAKE)
            os.chmod(fake, 0o755)
            out = os.path.join(tmp, "results.md")
            r = subprocess.run([sys.executable, os.path.join(HERE, "panel_hit_rate.py"), fake, "--instances", "2",
                                "--seed", str(SEED), "--timeout", "3", "--keep", os.path.join(tmp, "inst"),
                                "--out", out, "--hours", str(SHORT[0]), "--output", str(SHORT[1])],
                               capture_output=True, text=True)
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(out) as f:
                text = f.read()
            rows = [line for line in text.splitlines() if line.startswith("| 0 ") or line.startswith("| 1 ")]
            self.assertEqual(len(rows), 2, text)
            self.assertIn("| hit |", rows[0])
            self.assertIn("| 400 | 20 |", rows[0])  # simulations and refits summed from --stats
            self.assertIn("| timeout |", rows[1])
            self.assertIn("hit rate: 1/2 = 50 %", text)
            self.assertTrue(os.path.exists(os.path.join(tmp, "inst", "P00", "report.json")))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: test_panel_hit_rate.py THERMNET")
    THERMNET = sys.argv.pop(1)
    unittest.main()
