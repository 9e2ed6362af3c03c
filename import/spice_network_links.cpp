// The links, Cauer ladders, heaters, initial conditions and case of a SPICE netlist's network.

#include "import/spice_builder.hpp"

#include "lang/display_text.hpp"

#include <fmt/format.h>

namespace thermnet::importer::spice::detail {

Name NetworkBuilder::node_name(const std::string& flat) {
  return Name{flat, {}};
}

void NetworkBuilder::initial_conditions() {
  const bool uic = c_.tran && c_.tran->uic;
  if (!uic) {
    for (const auto& ic : c_.ics)
      report_.dropped(ic.at, fmt::format(".ic V({}) without UIC: ngspice holds the node there "
                                         "while it finds its operating point; thermnet starts "
                                         "from the steady state without holding it",
                                         shown(ic.node)));
    return;
  }
  for (const auto& ic : c_.ics) {
    if (ic.node == "0" || held_.count(ic.node)) {
      report_.note(ic.at, fmt::format("ignored: .ic of node {}, which is held", shown(ic.node)));
      continue;
    }
    auto it = node_index_.find(ic.node);
    if (it == node_index_.end()) {
      report_.dropped(ic.at, fmt::format(".ic of node {}, which is not written (an inner node of "
                                         "a Foster chain, or a node nothing touches)",
                                         shown(ic.node)));
      continue;
    }
    if (auto t = t0_.find(ic.node); t != t0_.end() && t->second.first != ic.value) {
      report_.error(ic.at, "duplicate-name",
                    fmt::format("node {} is given two initial conditions", shown(ic.node)),
                    {{t->second.second, "the other one"}});
      continue;
    }
    t0_[ic.node] = {ic.value, ic.at};
  }
  for (const auto& [node, value] : t0_)
    if (auto it = node_index_.find(node); it != node_index_.end())
      net_.nodes[it->second].T0 = temperature(value.first);
}

void NetworkBuilder::resistors() {
  for (std::size_t i = 0; i < c_.elements.size(); ++i) {
    const Element& e = c_.elements[i];
    if (!usable_[i] || e.kind != 'r') continue;
    Link l;
    l.kind = LinkKind::resistor;
    l.name = Name{e.name, {}};
    l.a = node_name(e.a);
    l.b = node_name(e.b);
    l.value = number(e.value);
    if (e.expr) l.value.scoped = *e.expr;
    l.origin = e.at;
    l.scope = e.scope;
    net_.links.push_back(std::move(l));
  }
}

void NetworkBuilder::cauer_ladders() {
  for (std::size_t chain = 0; chain < chains_.size(); ++chain) {
    const FosterChain& ch = chains_[chain];
    if (!ch.written) continue;
    std::vector<CauerStage> stages;
    try {
      stages = foster_to_cauer(ch.cells);
    } catch (const FosterError& e) {
      report_.error(ch.at, "foster-chain",
                    fmt::format("the Foster chain from {} to {} cannot be converted: {}",
                                shown(ch.driven), shown(ch.far), e.what()));
      continue;
    }
    const Name driven = node_name(ch.driven);
    const Name far = node_name(ch.far);
    const std::string base = ladder_key('n', chain, ch.driven);
    const std::string rbase = ladder_key('r', chain, ch.driven);
    // The ladder stands in the innermost instance that holds every element of the chain.
    std::size_t scope = c_.elements[ch.consumed.front()].scope;
    const auto inside = [&](std::size_t s, std::size_t outer) {
      for (; s != 0; s = c_.instances[s].parent)
        if (s == outer) return true;
      return outer == 0;
    };
    for (std::size_t i : ch.consumed)
      while (!inside(c_.elements[i].scope, scope))
        scope = c_.instances[scope].parent;
    const std::size_t n = stages.size();
    Node& d = net_.nodes[node_index_.at(ch.driven)];
    d.C = number(d.C.si + stages[0].C);
    d.what += (d.what.empty() ? "" : "; ") +
              fmt::format("C includes the Cauer ladder's {}", number_text(stages[0].C));
    for (std::size_t k = 1; k < n; ++k)
      net_.nodes.push_back({Name{base, static_cast<std::int64_t>(k)}, number(stages[k].C),
                            std::nullopt, "Cauer ladder node", ch.at, scope});
    for (std::size_t k = 1; k <= n; ++k) {
      Link l;
      l.kind = LinkKind::resistor;
      l.name = Name{rbase, static_cast<std::int64_t>(k)};
      l.a = k == 1 ? driven : Name{base, static_cast<std::int64_t>(k - 1)};
      l.b = k == n ? far : Name{base, static_cast<std::int64_t>(k)};
      l.value = number(stages[k - 1].R);
      l.what = "Cauer ladder";
      l.origin = ch.at;
      l.scope = scope;
      net_.links.push_back(std::move(l));
    }
    ladders_.emplace_back(chain, n);
  }
}

void NetworkBuilder::ladder_notes(const std::function<std::string(const std::string&)>& name_of) {
  const bool uic = c_.tran && c_.tran->uic;
  for (const auto& [chain, n] : ladders_) {
    const FosterChain& ch = chains_[chain];
    const std::string ladder_display = name_of(ladder_key('n', chain, ch.driven));
    std::string inner;
    for (std::size_t k = 0; k < ch.inner.size() && k < 5; ++k)
      inner += (k ? ", " : "") + shown(ch.inner[k]);
    if (ch.inner.size() > 5) inner += fmt::format(" and {} more", ch.inner.size() - 5);
    std::string text = fmt::format(
        "the Foster network from {} to {} ({} cell{}{}) is written as the equivalent Cauer ladder "
        "{}{}: the same Zth(t) seen from {} with {} held",
        name_of(ch.driven), name_of(ch.far), ch.cells.size(), ch.cells.size() == 1 ? "" : "s",
        inner.empty() ? "" : "; its inner nodes " + inner + " are not temperatures of anything",
        name_of(ch.driven), n > 1 ? fmt::format(", {}[1 .. {}]", ladder_display, n - 1) : "",
        name_of(ch.driven), name_of(ch.far));
    if (!ch.far_held)
      text += fmt::format("; {} is not held at a fixed temperature here, so where it moves the "
                          "response differs from the netlist's (the Foster form's inner nodes "
                          "are not physical)",
                          name_of(ch.far));
    if (uic)
      text += "; with UIC the ladder's nodes start at the initial temperature like the others";
    report_.note(ch.at, text);
  }
}

void NetworkBuilder::heaters() {
  for (std::size_t i = 0; i < c_.elements.size(); ++i) {
    const Element& e = c_.elements[i];
    if (!usable_[i] || e.kind != 'i') continue;
    // SPICE's current flows from the first node through the source to the second: it heats the
    // second node and cools the first.
    for (int side = 0; side < 2; ++side) {
      const std::string& node = side == 0 ? e.b : e.a;
      if (node == "0") continue;
      if (held_.count(node)) {
        report_.note(e.at, fmt::format("current source '{}' feeds node {}, which is held: that "
                                       "heat changes no temperature and is not written",
                                       shown(e.name), shown(node)));
        continue;
      }
      Heater h;
      h.name = Name{side == 0 ? e.name : e.name + ".out", {}};
      h.node = node_name(node);
      h.scope = e.scope;
      h.P = signal_of(e, side == 0 ? 1.0 : -1.0, false);
      h.origins.push_back(e.at);
      net_.heaters.push_back(std::move(h));
    }
  }
}

void NetworkBuilder::case_spec() {
  if (!c_.tran) {
    if (c_.op)
      report_.note(*c_.op, "the netlist asks for the operating point: run `thermnet simulate "
                           "MODEL --steady`");
    return;
  }
  const Tran& t = *c_.tran;
  CaseSpec cs;
  cs.name = "tran";
  cs.duration = number(t.stop);
  cs.origin = t.at;
  if (t.stop / t.step > max_output_rows) {
    cs.output = number(t.stop / max_output_rows);
    report_.note(t.at, fmt::format("TSTEP = {} would write {:.0f} rows: the case writes {:.0f}",
                                   number_text(t.step), t.stop / t.step, max_output_rows));
  } else if (t.step <= t.stop)
    cs.output = number(t.step);
  else
    report_.note(t.at, "TSTEP is longer than TSTOP: thermnet's default output interval is used");
  if (t.start > 0)
    report_.note(t.at, "TSTART only delays SPICE's output; thermnet writes every row from 0");
  cs.initial = t.uic ? "0" : "steady";
  net_.case_spec = std::move(cs);
}

} // namespace thermnet::importer::spice::detail
