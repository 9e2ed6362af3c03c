"""Hidden effects: what the truth has and the nominal model lacks.

Kinds (the first six are those of the diagnosis contract; the last two are the model-form errors
issue 14 adds):
  missing_link    a linear (conductance) or radiative path between two nodes or a node and a boundary
  missing_source  a constant heat gain (or loss) at a node
  capacity_error  a node's heat capacity times a factor
  heater_gain     a heater delivering a factor times its modelled power
  sensor_lag      a sensor reading its node through a first-order lag tau
  sensor_offset   a sensor reading with a constant bias
  heater_mass     a heater heating its node through its own thermal mass: in the truth it sits on
                  an extra node (capacity C, conductance G to the node the model attaches it to)
  event_loss      a conductance between a node and a boundary that exists only while an event is
                  on (the box's lid opened at the times listed in events.csv)
and issue 29's three mass and input forms:
  wall_mass       a mass inside a linear link a-b (an envelope, a bracket): the link's conductance G
                  is split around a node of capacity C, G/f on a's side and G/(1-f) on b's
  hidden_mass     a mass of capacity C tied to a node by G = C / tau (an object, furniture)
  input_split     a share of a heater's power heats another node b instead of its own

An effect's size is one number, its *strength* x (G, GR, |P|, |ln factor|, |factor - 1|, tau,
|offset|, the heater mass's time constant C/G, the event conductance); generate.py scales it so
that the effect alone moves some measured reading by about the scenario's target impact (peak,
in kelvin), within the physically plausible bounds below.
"""
from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

import numpy as np

from network import Heater, Link, Network, Node, Signal, capacity, conductance, sig4

KINDS = ("missing_link", "missing_source", "capacity_error", "heater_gain", "sensor_lag",
         "sensor_offset", "heater_mass", "event_loss", "wall_mass", "hidden_mass", "input_split")
SENSOR_KINDS = ("sensor_lag", "sensor_offset")
MASS_NODE = "hidden_mass"

# strength bounds per kind (and link mechanism)
BOUNDS = {
    "missing_link/linear": (0.005, 5.0),  # W/K
    "missing_link/radiation": (1e-3, 0.05),  # m^2
    "missing_source": (0.05, 30.0),  # W
    "capacity_error": (0.2, 1.6),  # |ln factor|: factor 1.22..5 (a forgotten mass) or 0.2..0.82
    "heater_gain": (0.1, 0.5),  # |factor - 1|
    "sensor_lag": (60.0, 1500.0),  # s
    "sensor_offset": (0.5, 2.0),  # K
    "heater_mass": (120.0, 2400.0),  # s, C/G of the heater's own mass
    "event_loss": (0.05, 20.0),  # W/K (air exchange through an open lid)
    "wall_mass": (120.0, 20000.0),  # s, C f (1 - f) / G of the mass inside the link
    "hidden_mass": (0.05, 10.0),  # its capacity / the node's
    "input_split": (0.1, 0.9),  # the share of the heater's power that heats the other node
}


@dataclass
class Effect:
    kind: str
    want_measured: bool  # the table's placement: the effect's (first) node measured or not
    mechanism: str | None = None  # missing_link: linear | radiation
    nodes: list[str] = field(default_factory=list)  # first: the node the placement refers to
    element: str | None = None  # heater_gain, heater_mass: the heater
    sign: float = 1.0
    strength: float = 0.0
    mass_ratio: float = 1.0  # heater_mass: its capacity / the node's
    share: float = 0.5  # wall_mass: the share of the link's resistance on the first node's side
    tau: float = 600.0  # hidden_mass: C / G, s
    impact: float = 0.0  # K, peak change of a measured reading by this effect alone

    @property
    def key(self) -> str:
        return f"{self.kind}/{self.mechanism}" if self.kind == "missing_link" else self.kind

    def bounded(self, x: float) -> float:
        lo, hi = BOUNDS[self.key]
        return float(np.clip(x, lo, hi))

    def values(self, net: Network, params: dict[str, float]) -> dict[str, float]:
        """The effect's size in the diagnosis report's names."""
        x = self.strength
        if self.kind == "missing_link":
            return {"G": x} if self.mechanism == "linear" else {"GR": x}
        if self.kind == "missing_source":
            return {"P": self.sign * x}
        if self.kind == "capacity_error":
            return {"factor": float(np.exp(self.sign * x))}
        if self.kind == "heater_gain":
            return {"factor": 1.0 + self.sign * x}
        if self.kind == "sensor_lag":
            return {"tau": x}
        if self.kind == "sensor_offset":
            return {"offset": self.sign * x}
        if self.kind == "heater_mass":
            c = sig4(self.mass_ratio * capacity(net.node(self.nodes[0]), params))
            return {"C": c, "G": sig4(c / x)}
        if self.kind == "wall_mass":
            g = conductance(next(lk for lk in net.links if lk.name == self.element), params)
            return {"C": sig4(x * g / (self.share * (1.0 - self.share))), "f": self.share}
        if self.kind == "hidden_mass":
            return {"C": sig4(x * capacity(net.node(self.nodes[0]), params)), "tau": self.tau}
        if self.kind == "input_split":
            return {"share": x}
        return {"G": x}  # event_loss


def _distances(net: Network, start: str) -> dict[str, int]:
    nodes = {n.name for n in net.nodes}
    dist, todo = {start: 0}, deque([start])
    while todo:
        a = todo.popleft()
        for b in net.neighbours(a):
            if b in nodes and b not in dist:
                dist[b] = dist[a] + 1
                todo.append(b)
    return dist


def _mean_temps(net: Network, base) -> dict[str, float]:
    """Mean temperature of every node and boundary over the base simulation's first case."""
    times, T, _ = base[0]
    out = {n.name: float(T[:, i].mean()) for i, n in enumerate(net.nodes)}
    c = net.cases[0]
    out.update({b: float(np.mean([s.at(t) for t in times])) for b, s in c.boundary_T.items()})
    return out


def randomize(e: Effect, rng) -> None:
    """The effect's sign (a source or a sink, a factor above or below 1, ...) and heater mass.
    Sources (dissipating parts) and forgotten masses are more common than sinks and overestimates."""
    e.sign = 1.0 if rng.uniform() < (0.7 if e.kind in ("missing_source", "capacity_error") else 0.5) else -1.0
    e.mass_ratio = sig4(rng.uniform(0.5, 1.5))
    # (drawn for their kinds only: the other kinds' scenarios keep the draws they always had)
    if e.kind == "wall_mass":
        e.share = sig4(rng.uniform(0.25, 0.75))
    if e.kind == "hidden_mass":
        e.tau = sig4(rng.uniform(300.0, 1800.0))


def sites(net: Network, e: Effect, base, rng, measured: set[str], taken: set[str]) -> list[tuple[list[str], str | None]]:
    """Candidate sites (nodes, heater) for e, most plausible first, on nodes measured or not as
    e.want_measured says (sensor kinds: measured), none in `taken`. base: the truth simulated
    without effects, [(times, T, sensors)] per case."""
    want = e.want_measured or e.kind in SENSOR_KINDS
    names = [n.name for n in net.nodes]
    ok = [a for a in names if (a in measured) == want and a not in taken]
    rng.shuffle(ok)
    times, T, _ = base[0]
    col = {a: i for i, a in enumerate(names)}
    swing = {a: float(np.ptp(T[:, col[a]])) for a in names}
    slope = {a: float(np.abs(np.diff(T[:, col[a]])).max()) for a in names}
    if e.kind == "missing_link":
        means = _mean_temps(net, base)
        if e.mechanism == "radiation":  # radiation matters from a node far hotter or colder than most
            mid = float(np.median([means[a] for a in names]))
            ok = sorted(ok, key=lambda a: -abs(means[a] - mid))[:8]
            rng.shuffle(ok)
        links = (_link_site(net, e, rng, means, a) for a in ok[:8])
        return [(lk, None) for lk in links if lk][:6]
    if e.kind == "missing_source":
        return [([a], None) for a in ok[:6]]
    if e.kind == "capacity_error":  # a node whose temperature moves, so its capacity matters
        ranked = sorted(ok, key=lambda a: -swing[a])
        return [([a], None) for a in ranked[: max(3, len(ranked) // 3)]][:6]
    if e.kind in ("heater_gain", "heater_mass"):
        hs = [h for h in net.heaters if h.node in ok]
        rng.shuffle(hs)
        return [([h.node], h.name) for h in hs]
    if e.kind == "sensor_lag":  # a sensor on a node that changes fast enough for a lag to show
        ranked = sorted(ok, key=lambda a: -slope[a])[:5]
        rng.shuffle(ranked)
        return [([a], None) for a in ranked]
    if e.kind == "sensor_offset":
        return [([a], None) for a in ok[:6]]
    if e.kind == "wall_mass":  # a linear link with a node end; links to a boundary (walls) first
        out = []
        links = [lk for lk in net.links if lk.kind != "radiation" and not lk.during_event]
        rng.shuffle(links)
        links.sort(key=lambda lk: not (net.is_boundary(lk.a) or net.is_boundary(lk.b)))
        for lk in links:
            a = next((x for x in (lk.a, lk.b) if x in ok), None)
            if a is not None:
                out.append(([a, lk.b if a == lk.a else lk.a], lk.name))
        return out[:6]
    if e.kind == "hidden_mass":  # a node whose temperature moves, so a mass tied to it matters
        ranked = sorted(ok, key=lambda a: -swing[a])
        return [([a], None) for a in ranked[: max(3, len(ranked) // 3)]][:6]
    if e.kind == "input_split":  # a heater's power partly heating a node one or two links away
        hs = [h for h in net.heaters if h.node in ok]
        rng.shuffle(hs)
        out = []
        for h in hs:
            dist = _distances(net, h.node)
            near = sorted(b for b, d in dist.items() if 1 <= d <= 2)
            if near:
                out.append(([h.node, str(rng.choice(near))], h.name))
        return out
    if e.kind == "event_loss":  # the box's lid: the inside air mixes with the room's
        if "air_in" in names:
            return [(["air_in", "room"], None)] if "air_in" in ok else []
        bounds = [b.name for b in net.boundaries]
        return [([a, str(rng.choice(bounds))], None) for a in ok[:4]]
    raise ValueError(f"unknown effect kind {e.kind}")


def _link_site(net: Network, e: Effect, rng, means, a: str) -> list[str] | None:
    """A plausible missing path from node a: to a boundary it has no path to, or to a node 2-4
    links away (a bolt or a cable bypassing the modelled route). Radiation goes to a boundary at
    least 15 K colder or warmer on average, else to one of the three nodes 2-4 links away whose
    temperature differs most. None when a has no such partner."""
    free_b = [b.name for b in net.boundaries if not net.linked(a, b.name)]
    if e.mechanism == "radiation":
        free_b = [b for b in free_b if abs(means[b] - means[a]) >= 15.0]
    if free_b and rng.uniform() < (0.6 if e.mechanism == "radiation" else 0.5):
        return [a, str(rng.choice(free_b))]
    dist = _distances(net, a)
    far = [b for b, d in dist.items() if 2 <= d <= 4 and not net.linked(a, b)]
    if e.mechanism == "radiation":
        far = sorted(far, key=lambda b: -abs(means[b] - means[a]))[:3]
    if far:
        return [a, str(rng.choice(far))]
    return [a, str(rng.choice(free_b))] if free_b else None


def apply(net: Network, effects: list[Effect], params: dict[str, float]):
    """The truth: a copy of net with the structural effects added (a heater mass's capacity is
    relative to its node's at the given params); and the sensor effects as {node: tau} and
    {node: offset}."""
    truth = net.copy()
    lags, offsets = {}, {}
    for e in effects:
        x = e.strength
        if e.kind == "missing_link":
            a, b = e.nodes
            keys = {"G": x} if e.mechanism == "linear" else {"GR": x}
            truth.links.append(Link(f"hidden_{a}_{b}", "conductance" if e.mechanism == "linear" else "radiation", a, b, keys))
        elif e.kind == "missing_source":
            truth.heaters.append(Heater(f"hidden_src_{e.nodes[0]}", e.nodes[0]))
            for c in truth.cases:
                c.heater_P[f"hidden_src_{e.nodes[0]}"] = Signal.const(e.sign * x)
        elif e.kind == "capacity_error":
            nd = truth.node(e.nodes[0])
            nd.C = nd.C * float(np.exp(e.sign * x))
        elif e.kind == "heater_gain":
            for c in truth.cases:
                c.heater_P[e.element] = c.heater_P[e.element].scaled(1.0 + e.sign * x)
        elif e.kind == "heater_mass":
            a = e.nodes[0]
            c_mass = sig4(e.mass_ratio * capacity(net.node(a), params))
            m = f"{MASS_NODE}_{e.element}"
            truth.nodes.append(Node(m, c_mass, "the heater's own mass"))
            truth.links.append(Link(f"hidden_g_{m}", "conductance", m, a, {"G": sig4(c_mass / x)}))
            next(h for h in truth.heaters if h.name == e.element).node = m
        elif e.kind == "wall_mass":
            a, b = e.nodes
            lk = next(k for k in truth.links if k.name == e.element)
            g, f = conductance(lk, params), e.share
            m = f"hidden_wall_{e.element}"
            truth.nodes.append(Node(m, sig4(x * g / (f * (1.0 - f))), "the mass inside the link"))
            truth.links.remove(lk)
            truth.links.append(Link(f"hidden_wall_a_{e.element}", "conductance", a, m, {"G": sig4(g / f)}))
            truth.links.append(Link(f"hidden_wall_b_{e.element}", "conductance", m, b, {"G": sig4(g / (1.0 - f))}))
        elif e.kind == "hidden_mass":
            a = e.nodes[0]
            c_mass = sig4(x * capacity(net.node(a), params))
            m = f"hidden_obj_{a}"
            truth.nodes.append(Node(m, c_mass, "a mass tied to the node"))
            truth.links.append(Link(f"hidden_g_{m}", "conductance", m, a, {"G": sig4(c_mass / e.tau)}))
        elif e.kind == "input_split":
            name = f"hidden_split_{e.element}"
            truth.heaters.append(Heater(name, e.nodes[1]))
            for c in truth.cases:
                c.heater_P[name] = c.heater_P[e.element].scaled(x)
                c.heater_P[e.element] = c.heater_P[e.element].scaled(1.0 - x)
        elif e.kind == "event_loss":
            a, b = e.nodes
            truth.links.append(Link(f"hidden_event_{a}_{b}", "conductance", a, b, {"G": x}, during_event="lid"))
        elif e.kind == "sensor_lag":
            lags[e.nodes[0]] = x
        elif e.kind == "sensor_offset":
            offsets[e.nodes[0]] = e.sign * x
    return truth, lags, offsets

