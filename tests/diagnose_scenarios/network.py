"""The generator's own description of a thermal network: params, nodes, boundaries, links,
heaters and cases with their input schedules.

It is written out as a .tnet model by tnet_writer.py and integrated by truth.py with SciPy; the
two never share code with thermnet. Every number is rounded to 4 significant digits when it is
made (sig4), so the .tnet text and the SciPy integration use exactly the same values.
"""
from __future__ import annotations

import copy
from dataclasses import dataclass, field

import numpy as np

SIGMA_SB = 5.670374419e-8  # W/(m^2 K^4)
ZERO_C = 273.15


def sig4(x: float) -> float:
    """x rounded to 4 significant digits (the precision every generated number is written with)."""
    return float(f"{x:.4g}")


def num(x: float) -> str:
    """x as .tnet text (the shortest form that reads back to the same float)."""
    return repr(float(x))


@dataclass
class Signal:
    """A constant, a step(t0: v0, ...) or a pwl(t0: v0, ...) signal (times s, values SI/degC)."""

    kind: str  # "const" | "step" | "pwl"
    points: list[tuple[float, float]]

    @staticmethod
    def const(v: float) -> Signal:
        return Signal("const", [(0.0, v)])

    def at(self, t: float) -> float:
        """The value at time t (a step holds v_k on [t_k, t_k+1))."""
        if self.kind == "const":
            return self.points[0][1]
        if self.kind == "step":
            v = self.points[0][1]
            for tk, vk in self.points:
                if t >= tk:
                    v = vk
            return v
        ts, vs = zip(*self.points)
        return float(np.interp(t, ts, vs))

    def corners(self) -> list[float]:
        """Times where the signal or its slope jumps (the integrator restarts there)."""
        return [] if self.kind == "const" else [t for t, _ in self.points]

    def scaled(self, factor: float) -> Signal:
        return Signal(self.kind, [(t, sig4(v * factor)) for t, v in self.points])

    def tnet(self, unit: str = "") -> str:
        u = f" [{unit}]" if unit else ""
        if self.kind == "const":
            return num(self.points[0][1]) + u
        return f"{self.kind}(" + ", ".join(f"{num(t)}: {num(v)}{u}" for t, v in self.points) + ")"


@dataclass
class Param:
    name: str
    nominal: float
    lo: float
    hi: float
    unit: str  # .tnet unit text, "" for dimensionless
    desc: str


# A key's value is a number or the name of a param.
Value = float | str


@dataclass
class Node:
    name: str
    C: float  # J/K, or the volume in m^3 when c_param names a volumetric capacity param
    desc: str = ""
    c_param: str | None = None


@dataclass
class Boundary:
    name: str
    desc: str = ""


@dataclass
class Link:
    """A two-terminal element. kind: conductance (G), convection/contact (h, A), conduction
    (k, L, A) or radiation (A, eps1, eps2: GR = A / (1/eps1 + 1/eps2 - 1); or GR).
    `during_event` names an event: the link then conducts only while that event is on (the
    hidden event loss; .tnet has no such element, so it is never written)."""

    name: str
    kind: str
    a: str
    b: str
    keys: dict[str, Value]
    desc: str = ""
    during_event: str | None = None


@dataclass
class Heater:
    name: str
    node: str
    desc: str = ""


@dataclass
class Case:
    name: str
    duration: float
    output: float
    initial: float
    boundary_T: dict[str, Signal]
    heater_P: dict[str, Signal]
    events: list[tuple[str, float, float]] = field(default_factory=list)  # (name, start, end)


@dataclass
class Network:
    name: str
    shape: str
    desc: str
    params: list[Param]
    nodes: list[Node]
    boundaries: list[Boundary]
    links: list[Link]
    heaters: list[Heater]
    cases: list[Case]

    def copy(self) -> Network:
        return copy.deepcopy(self)

    def param(self, name: str) -> Param:
        return next(p for p in self.params if p.name == name)

    def node(self, name: str) -> Node:
        return next(n for n in self.nodes if n.name == name)

    def is_boundary(self, name: str) -> bool:
        return any(b.name == name for b in self.boundaries)

    def linked(self, a: str, b: str) -> bool:
        return any({lk.a, lk.b} == {a, b} for lk in self.links)

    def neighbours(self, a: str) -> list[str]:
        return [lk.b if lk.a == a else lk.a for lk in self.links if a in (lk.a, lk.b)]


def value(v: Value, params: dict[str, float]) -> float:
    return params[v] if isinstance(v, str) else float(v)


def capacity(node: Node, params: dict[str, float]) -> float:
    """The node's heat capacity [J/K] at the given param values."""
    return node.C * params[node.c_param] if node.c_param else node.C


def conductance(link: Link, params: dict[str, float]) -> float:
    """G [W/K] of a linear link, or GR [m^2] of a radiation link, at the given param values."""
    k = {key: value(v, params) for key, v in link.keys.items()}
    if link.kind == "conductance":
        return k["G"]
    if link.kind in ("convection", "contact"):
        return k["h"] * k["A"]
    if link.kind == "conduction":
        return k["k"] * k["A"] / k["L"]
    if link.kind == "radiation":
        if "GR" in k:
            return k["GR"]
        return k["A"] / (1.0 / k["eps1"] + 1.0 / k["eps2"] - 1.0)
    raise ValueError(f"unknown link kind {link.kind}")


def nominal_params(net: Network) -> dict[str, float]:
    return {p.name: p.nominal for p in net.params}
