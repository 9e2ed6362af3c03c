#!/usr/bin/python3
"""The scorer's matching rules (score.py) on hand-written truths and reports; needs no thermnet."""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import score as sc  # noqa: E402


def effect(kind, nodes, mechanism=None, element=None, values=None):
    return {"kind": kind, "nodes": nodes, "mechanism": mechanism, "element": element,
            "values": values or {"G": 0.5}, "impact_K": 3.0, "measured": True}


def truth(*effects, control=None, constant_heaters=()):
    return {"effects": list(effects), "control": control, "constant_heaters": list(constant_heaters)}


def finding(kind, nodes=(), mechanism=None, element=None, candidates=None, values=None):
    f = {"kind": kind, "nodes": list(nodes), "values": values or {}}
    if mechanism:
        f["mechanism"] = mechanism
    if element:
        f["element"] = element
    if candidates is not None:
        f["candidates"] = candidates
    return f


def report(*findings):
    return {"baseline": {"rmse": 1.0}, "findings": list(findings)}


LINK = effect("missing_link", ["a", "b"], "linear", values={"G": 0.5})


class Links(unittest.TestCase):
    def test_node_order_does_not_matter(self):
        v = sc.score(report(finding("missing_link", ["b", "a"], "linear")), truth(LINK))
        self.assertEqual(v["score"], 1.0)
        self.assertTrue(v["mechanism_ok"])

    def test_mechanism_is_scored_apart(self):
        v = sc.score(report(finding("missing_link", ["a", "b"], "radiation")), truth(LINK))
        self.assertEqual(v["score"], 1.0)
        self.assertFalse(v["mechanism_ok"])

    def test_neighbouring_pair_is_a_miss(self):
        v = sc.score(report(finding("missing_link", ["a", "c"], "linear")), truth(LINK))
        self.assertEqual(v["score"], 0.0)
        self.assertEqual(len(v["spurious"]), 1)

    def test_ambiguity_set_containing_the_cause_is_a_hit(self):
        rivals = [finding("missing_link", ["a", "c"]), finding("missing_source", ["a"]),
                  finding("missing_link", ["b", "a"])]
        v = sc.score(report(finding("missing_link", ["a", "c"], "linear", candidates=rivals)), truth(LINK))
        self.assertEqual(v["score"], 1.0)
        self.assertEqual(v["spurious"], [])

    def test_a_padded_set_does_not_count_beyond_its_first_members(self):
        rivals = [finding("missing_source", [f"n{k}"]) for k in range(sc.MAX_SET)] + [finding("missing_link", ["a", "b"])]
        v = sc.score(report(finding("missing_link", ["a", "c"], candidates=rivals)), truth(LINK))
        self.assertEqual(v["score"], 0.0)

    def test_fitted_ratio_reads_the_matching_member(self):
        f = finding("missing_link", ["b", "a"], "linear", values={"G": 0.6, "h_air": 7.0})
        self.assertAlmostEqual(sc.fitted_ratio(f, LINK, truth(LINK)), 1.2)


class Ranking(unittest.TestCase):
    def test_parameter_finding_is_skipped(self):
        v = sc.score(report(finding("parameter"), finding("missing_link", ["a", "b"])), truth(LINK))
        self.assertEqual(v["score"], 1.0)

    def test_cause_ranked_second_is_a_miss(self):
        v = sc.score(report(finding("sensor_offset", ["z"]), finding("missing_link", ["a", "b"])), truth(LINK))
        self.assertEqual(v["score"], 0.0)
        self.assertEqual(v["effects"][0]["rank"], 2)

    def test_no_finding_is_a_miss(self):
        self.assertEqual(sc.score(report(), truth(LINK))["score"], 0.0)

    def test_failed_diagnosis_is_a_miss(self):
        self.assertEqual(sc.score(None, truth(LINK))["score"], 0.0)


class NewKinds(unittest.TestCase):
    MASS = effect("heater_mass", ["n3"], element="q1", values={"C": 30.0, "G": 0.1})
    EVENT = effect("event_loss", ["air_in", "room"], values={"G": 2.0})

    def test_heater_mass_in_full(self):
        self.assertEqual(sc.score(report(finding("heater_mass", ["n3"], element="q1")), truth(self.MASS))["score"], 1.0)

    def test_source_capacity_or_gain_at_the_heater_is_partial(self):
        for f in (finding("missing_source", ["n3"]), finding("capacity_error", ["n3"]),
                  finding("heater_gain", ["n3"], element="q1")):
            self.assertEqual(sc.score(report(f), truth(self.MASS))["score"], 0.5, f)

    def test_source_elsewhere_is_a_miss(self):
        self.assertEqual(sc.score(report(finding("missing_source", ["n4"])), truth(self.MASS))["score"], 0.0)

    def test_event_loss_in_full_and_a_constant_link_partial(self):
        self.assertEqual(sc.score(report(finding("event_loss", ["room", "air_in"])), truth(self.EVENT))["score"], 1.0)
        self.assertEqual(sc.score(report(finding("missing_link", ["room", "air_in"])), truth(self.EVENT))["score"], 0.5)


class HeaterGain(unittest.TestCase):
    GAIN = effect("heater_gain", ["n2"], element="film", values={"factor": 1.3})

    def test_by_element(self):
        self.assertEqual(sc.score(report(finding("heater_gain", ["n2"], element="film")), truth(self.GAIN))["score"], 1.0)
        self.assertEqual(sc.score(report(finding("heater_gain", ["n2"], element="other")), truth(self.GAIN))["score"], 0.0)

    def test_a_source_equals_the_gain_of_a_constant_heater_only(self):
        src = report(finding("missing_source", ["n2"]))
        self.assertEqual(sc.score(src, truth(self.GAIN, constant_heaters=["film"]))["score"], 1.0)
        self.assertEqual(sc.score(src, truth(self.GAIN))["score"], 0.0)


class TwoEffects(unittest.TestCase):
    OFFSET = effect("sensor_offset", ["c"], values={"offset": 1.0})

    def test_both_found_in_full(self):
        v = sc.score(report(finding("missing_link", ["a", "b"]), finding("sensor_offset", ["c"])), truth(LINK, self.OFFSET))
        self.assertEqual((v["score"], v["both_found"]), (1.0, True))

    def test_second_cause_missing(self):
        v = sc.score(report(finding("missing_link", ["a", "b"]), finding("sensor_offset", ["d"])), truth(LINK, self.OFFSET))
        self.assertEqual((v["score"], v["both_found"]), (0.0, False))

    def test_second_cause_beyond_the_window(self):
        fs = [finding("missing_link", ["a", "b"]), finding("missing_source", ["x"]), finding("missing_source", ["y"]),
              finding("sensor_offset", ["c"])]
        self.assertFalse(sc.score(report(*fs), truth(LINK, self.OFFSET))["both_found"])

    def test_partial_hit_makes_half(self):
        mass = NewKinds.MASS
        v = sc.score(report(finding("missing_link", ["a", "b"]), finding("missing_source", ["n3"])), truth(LINK, mass))
        self.assertEqual((v["score"], v["both_found"]), (0.5, True))


class Controls(unittest.TestCase):
    def test_parameter_finding_passes(self):
        self.assertEqual(sc.score(report(finding("parameter")), truth(control="params"))["score"], 1.0)

    def test_any_structural_finding_fails(self):
        v = sc.score(report(finding("parameter"), finding("sensor_offset", ["a"])), truth(control="params"))
        self.assertEqual(v["score"], 0.0)
        self.assertEqual(len(v["spurious"]), 1)


class Acceptance(unittest.TestCase):
    @staticmethod
    def row(score, control=None, both=None):
        return {"verdict": {"score": score, "control": control, "both_found": both}}

    def test_thresholds(self):
        good = [self.row(1.0)] * 8 + [self.row(0.5), self.row(1.0, "params"), self.row(1.0, both=True)]
        self.assertTrue(sc.acceptance(good)["accepted"])  # mean 10.5 / 11 = 0.955
        self.assertFalse(sc.acceptance(good[:-1] + [self.row(0.0, both=False)])["accepted"])
        self.assertFalse(sc.acceptance(good[:-2] + [self.row(0.0, "params"), good[-1]])["controls_ok"])
        self.assertFalse(sc.acceptance([self.row(1.0)] * 8 + [self.row(0.0)] * 2)["score_ok"])



WALL = effect("wall_mass", ["a", "out"], element="g_a_out", values={"C": 4e4, "f": 0.4})
OBJECT = effect("hidden_mass", ["a"], values={"C": 900.0, "tau": 600.0})
SPLIT = effect("input_split", ["a", "b"], element="h", values={"share": 0.4})


class Masses(unittest.TestCase):
    def test_wall_named_by_its_link(self):
        v = sc.score(report(finding("wall_mass", ["a", "out"], element="g_a_out")), truth(WALL))
        self.assertEqual(v["score"], 1.0)

    def test_wall_in_another_link_is_a_miss(self):
        v = sc.score(report(finding("wall_mass", ["a", "c"], element="g_a_c")), truth(WALL))
        self.assertEqual(v["score"], 0.0)

    def test_a_mass_at_an_end_of_the_wall_is_partial(self):
        v = sc.score(report(finding("hidden_mass", ["a"])), truth(WALL))
        self.assertEqual(v["score"], 0.5)

    def test_hidden_mass_at_its_node(self):
        self.assertEqual(sc.score(report(finding("hidden_mass", ["a"])), truth(OBJECT))["score"], 1.0)
        self.assertEqual(sc.score(report(finding("capacity_error", ["a"])), truth(OBJECT))["score"], 0.5)
        self.assertEqual(sc.score(report(finding("hidden_mass", ["b"])), truth(OBJECT))["score"], 0.0)

    def test_split_needs_heater_and_both_nodes(self):
        self.assertEqual(sc.score(report(finding("input_split", ["a", "b"], element="h")), truth(SPLIT))["score"], 1.0)
        self.assertEqual(sc.score(report(finding("input_split", ["a", "c"], element="h")), truth(SPLIT))["score"], 0.0)
        self.assertEqual(sc.score(report(finding("heater_gain", ["a"], element="h")), truth(SPLIT))["score"], 0.5)
        self.assertEqual(sc.score(report(finding("missing_source", ["b"])), truth(SPLIT))["score"], 0.5)

if __name__ == "__main__":
    unittest.main()
