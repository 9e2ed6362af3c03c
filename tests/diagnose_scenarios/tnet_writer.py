"""Writes a Network as .tnet text: the nominal model a user would have (ranged params at their
nominal values, a `data` file per case), or -- for the generator's self-check only -- the truth
with its params at the true values."""
from __future__ import annotations

from network import Network, num

KEY_UNITS = {"G": "W/K", "h": "W/(m^2*K)", "A": "m^2", "k": "W/(m*K)", "L": "m", "GR": "m^2"}


def _key(key: str, v) -> str:
    if isinstance(v, str):
        return f"{key} = {v}"
    unit = "" if key.startswith("eps") else f" [{KEY_UNITS[key]}]"
    return f"{key} = {num(v)}{unit}"


def _quote(text: str) -> str:
    return f' "{text}"' if text else ""


def write_tnet(
    net: Network, path: str, header: str, param_values: dict[str, float] | None = None,
    with_data: bool = True,
) -> None:
    """Writes the model; param_values replaces the params' values (ranges kept)."""
    out = [f"# {line}" if line else "#" for line in header.splitlines()]
    out.append(f"model {net.name}")
    out.append("")
    for p in net.params:
        v = param_values[p.name] if param_values else p.nominal
        unit = f" [{p.unit}]" if p.unit else ""
        out.append(f"param {p.name} = {num(v)}{unit} range {num(p.lo)} .. {num(p.hi)}{_quote(p.desc)}")
    out.append("")
    for b in net.boundaries:
        out.append(f"boundary {b.name} T = {num(net.cases[0].boundary_T[b.name].at(0.0))}{_quote(b.desc)}")
    for n in net.nodes:
        c = f"{n.c_param} * {num(n.C)} [m^3]" if n.c_param else f"{num(n.C)} [J/K]"
        out.append(f"node {n.name} C = {c}{_quote(n.desc)}")
    for lk in net.links:
        if lk.during_event:
            raise ValueError(f"link {lk.name} exists only during events: .tnet cannot say so")
        keys = " ".join(_key(k, v) for k, v in lk.keys.items())
        out.append(f"{lk.kind} {lk.name} {lk.a} {lk.b} {keys}{_quote(lk.desc)}")
    for h in net.heaters:
        out.append(f"heater {h.name} {h.node} P = 0 [W]{_quote(h.desc)}")
    for c in net.cases:
        out.append("")
        out.append(f"case {c.name} {{")
        out.append(f"  duration = {num(c.duration)} [s]; output = {num(c.output)} [s]; initial = {num(c.initial)}")
        for b, sig in c.boundary_T.items():
            out.append(f"  {b}.T = {sig.tnet()}")
        for h, sig in c.heater_P.items():
            out.append(f"  {h}.P = {sig.tnet('W')}")
        if with_data:
            out.append(f'  data "{c.name}.csv"')
        out.append("}")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
