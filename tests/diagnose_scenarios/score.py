"""Scores a `thermnet diagnose --json` report against a scenario's truth (truth.json).

A finding's kind must be the truth's kind name (effects.py): the contract's kinds, and for issue
14's two new hypotheses `heater_mass` and `event_loss`.

Matching rules (a *member* of a finding is the finding itself or one of its `candidates`, the
ambiguity set; only the first MAX_SET members, finding first, count, so a set cannot be padded):

- missing_link: same two names in either order; the mechanism (linear/radiation) does not decide
  the match and is scored separately (`mechanism_ok`).
- missing_source, capacity_error, sensor_lag, sensor_offset: same node.
- heater_gain: same heater `element` (or, without `element`, the heater's node). A missing_source
  at the heater's node also matches in full when that heater is constant in every case (then the
  two are the same effect and no data can tell them apart).
- heater_mass (a heater heating its node through its own thermal mass): a `heater_mass` finding
  naming the heater (`element`) or its node matches in full; a missing_source, capacity_error or
  heater_gain at that heater or node is a PARTIAL hit (it names the right place, not the cause).
- event_loss (a loss only while an event is on): an `event_loss` finding with the same two names
  matches in full; a missing_link between the same two names is a PARTIAL hit.
- wall_mass (a mass inside a link): a `wall_mass` finding naming the link (`element`) or its two
  ends matches in full; a hidden_mass or capacity_error at one of its ends is a PARTIAL hit.
- hidden_mass (a mass tied to a node): a `hidden_mass` finding at the node matches in full; a
  capacity_error at the node, or a wall_mass with the node as an end, is a PARTIAL hit.
- input_split (a share of a heater's power heating another node): an `input_split` finding naming
  the heater and both nodes matches in full; a heater_gain at that heater, or a missing_source at
  the other node, is a PARTIAL hit.
- A `parameter` finding never matches a structural effect, and is never counted against a
  scenario: every scenario except the `nothing` control has its ranged params off, so
  recalibrating them is always true.

Verdicts:
- Scenario with effects: the FIRST structural finding (skipping `parameter`) decides the rank-1
  result: full (1), partial (0.5) or miss (0). With two effects the scenario scores 1 only when
  the first structural finding matches one of them in full AND each effect is matched in full by
  one of the first (number of effects + 1) structural findings; 0.5 when the same holds with
  partial hits allowed; else 0. `both_found` (partial allowed) is the issue's "both causes found".
- Control (no effect): passes (1) when the report has no structural finding at all.
- Spurious: structural findings none of whose members matches any effect (listed, not scored,
  except on controls where any structural finding fails the scenario).
- A scenario whose diagnosis failed or timed out scores 0.

Acceptance (issue 14): mean scenario score >= 0.90 over the whole table, every control passes,
every two-effect scenario has both causes found.
"""
from __future__ import annotations

MAX_SET = 5
ACCEPT_SCORE = 0.90

_RANK = {"full": 2, "partial": 1, None: 0}


def structural(report: dict) -> list[dict]:
    return [f for f in report.get("findings", []) if f.get("kind") != "parameter"]


def members(finding: dict) -> list[dict]:
    """The finding and its ambiguity set, deduplicated, at most MAX_SET."""
    out, seen = [], set()
    for m in [finding] + list(finding.get("candidates") or []):
        key = (m.get("kind"), tuple(sorted(m.get("nodes") or [])), m.get("element"), m.get("mechanism"))
        if key not in seen:
            seen.add(key)
            out.append(m)
    return out[:MAX_SET]


def match_member(m: dict, effect: dict, truth: dict) -> str | None:
    """'full', 'partial' or None: how member m of a finding matches a true effect."""
    kind, nodes, element = m.get("kind"), set(m.get("nodes") or []), m.get("element")
    ek, en = effect["kind"], set(effect["nodes"])
    if ek in ("missing_link", "event_loss") and kind == ek:
        return "full" if nodes == en else None
    if ek in ("missing_source", "capacity_error", "sensor_lag", "sensor_offset"):
        return "full" if kind == ek and nodes == en else None
    heater = effect.get("element")
    at_heater = element == heater if element else en <= nodes
    if ek == "heater_gain":
        if kind == "heater_gain" and at_heater:
            return "full"
        constant = heater in truth.get("constant_heaters", [])
        return "full" if kind == "missing_source" and nodes == en and constant else None
    if ek == "heater_mass":
        if kind == "heater_mass" and at_heater:
            return "full"
        if kind in ("missing_source", "capacity_error") and nodes == en:
            return "partial"
        return "partial" if kind == "heater_gain" and at_heater else None
    if ek == "event_loss" and kind == "missing_link" and nodes == en:
        return "partial"
    if ek == "wall_mass":
        if kind == "wall_mass" and (element == heater if element else nodes == en):
            return "full"
        return "partial" if kind in ("hidden_mass", "capacity_error") and nodes <= en else None
    if ek == "hidden_mass":
        if kind == "hidden_mass" and nodes == en:
            return "full"
        if kind == "capacity_error" and nodes == en:
            return "partial"
        return "partial" if kind == "wall_mass" and en <= nodes else None
    if ek == "input_split":
        if kind == "input_split" and element == heater and nodes == en:
            return "full"
        if kind == "heater_gain" and at_heater:
            return "partial"
        b = set(effect["nodes"][1:])
        return "partial" if kind == "missing_source" and nodes == b else None
    return None


def match_finding(finding: dict, effect: dict, truth: dict) -> str | None:
    best = None
    for m in members(finding):
        r = match_member(m, effect, truth)
        if _RANK[r] > _RANK[best]:
            best = r
    return best


def _best(a, b):
    return a if _RANK[a] >= _RANK[b] else b


def score(report: dict | None, truth: dict) -> dict:
    """The scenario's verdict (see the module doc); report None: diagnosis failed."""
    effects = truth["effects"]
    out = {"score": 0.0, "first": None, "both_found": None, "spurious": [], "effects": [],
           "control": truth.get("control"), "mechanism_ok": None}
    if report is None:
        if len(effects) > 1:
            out["both_found"] = False
        return out
    found = structural(report)
    out["spurious"] = [f for f in found if not any(match_finding(f, e, truth) for e in effects)]
    if not effects:
        out["score"] = 1.0 if not found else 0.0
        return out
    first = match_finding(found[0], effects[0], truth) if found else None
    for e in effects[1:]:
        if found:
            first = _best(first, match_finding(found[0], e, truth))
    out["first"] = first
    window = found[: len(effects) + 1]
    per_effect = []
    for e in effects:
        best, where = None, None
        for k, f in enumerate(window):
            r = match_finding(f, e, truth)
            if _RANK[r] > _RANK[best]:
                best, where = r, k
        per_effect.append({"match": best, "rank": None if where is None else where + 1,
                           "finding": None if where is None else window[where]})
    out["effects"] = per_effect
    if len(effects) == 1:
        out["score"] = {"full": 1.0, "partial": 0.5, None: 0.0}[first]
    else:
        out["both_found"] = all(p["match"] for p in per_effect)
        if first == "full" and all(p["match"] == "full" for p in per_effect):
            out["score"] = 1.0
        elif first and out["both_found"]:
            out["score"] = 0.5
    links = [(e, p) for e, p in zip(effects, per_effect) if e["kind"] == "missing_link" and p["match"]]
    if links:
        out["mechanism_ok"] = all(_mechanism_of(p["finding"], e, truth) == e["mechanism"] for e, p in links)
    return out


def _mechanism_of(finding: dict, effect: dict, truth: dict) -> str | None:
    for m in members(finding):
        if match_member(m, effect, truth) == "full":
            return m.get("mechanism")
    return None


def fitted_ratio(finding: dict | None, effect: dict, truth: dict) -> float | None:
    """Fitted / true size of the effect, from the member that matches it in full (the first
    value the truth states: G, GR, P, factor, tau, offset, C)."""
    if finding is None:
        return None
    for m in members(finding):
        if match_member(m, effect, truth) == "full" and m.get("kind") == effect["kind"]:
            key = next(iter(effect["values"]))
            v = (m.get("values") or {}).get(key)
            if v is not None and effect["values"][key]:
                return float(v) / effect["values"][key]
    return None


def acceptance(results: list[dict]) -> dict:
    """The issue's three conditions over scored scenarios [{'verdict': score(...), ...}]."""
    scores = [r["verdict"]["score"] for r in results]
    controls = [r for r in results if r["verdict"]["control"]]
    doubles = [r for r in results if r["verdict"]["both_found"] is not None]
    mean = sum(scores) / len(scores) if scores else 0.0
    out = {
        "scenarios": len(results),
        "score": mean,
        "score_ok": mean >= ACCEPT_SCORE,
        "controls_clean": sum(r["verdict"]["score"] == 1.0 for r in controls),
        "controls": len(controls),
        "two_effect_found": sum(bool(r["verdict"]["both_found"]) for r in doubles),
        "two_effect": len(doubles),
    }
    out["controls_ok"] = out["controls_clean"] == out["controls"]
    out["two_effect_ok"] = out["two_effect_found"] == out["two_effect"]
    out["accepted"] = out["score_ok"] and out["controls_ok"] and out["two_effect_ok"]
    return out
