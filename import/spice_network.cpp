#include "import/spice_network.hpp"

#include "import/spice_builder.hpp"
#include "import/spice_cards.hpp"
#include "import/spice_fold.hpp"
#include "lang/display_text.hpp"

#include <fmt/format.h>

#include <set>

namespace thermnet::importer::spice {

namespace detail {

std::string shown(const std::string& s) {
  return lang::excerpt_for_display(s);
}

Value number(double v) {
  return {number_text(v), v};
}

/// A temperature in volts (degC) as a thermnet value (kelvin).
Value temperature(double v) {
  return {number_text(v), v + 273.15};
}

/// A source's value as a signal, times `sign`; `temperature` for a V source.
Signal signal_of(const Element& e, double sign, bool is_temperature) {
  Signal s;
  const auto value = [&](double v) {
    return is_temperature ? temperature(sign * v) : number(sign * v);
  };
  if (e.pwl.empty()) {
    s.constant = value(e.value);
    if (e.expr) s.constant.scoped = sign > 0 ? *e.expr : "-(" + *e.expr + ")";
    return s;
  }
  for (std::size_t k = 0; k < e.pwl.size(); ++k) {
    s.points.emplace_back(number(e.pwl[k].first), value(e.pwl[k].second));
    if (e.pwl_expr.size() == e.pwl.size()) {
      const auto& [t, v] = e.pwl_expr[k];
      s.points.back().first.scoped = t;
      s.points.back().second.scoped = sign > 0 ? v : "-(" + v + ")";
    }
  }
  return s;
}

std::string display(const std::string& flat) {
  if (flat == "0") return "gnd";
  std::string out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t dot = flat.find('.', start);
    out += sanitize(flat.substr(start, dot == std::string::npos ? dot : dot - start));
    if (dot == std::string::npos) break;
    out += '.';
    start = dot + 1;
  }
  return lang::excerpt_for_display(out);
}

std::string ladder_key(char kind, std::size_t chain, const std::string& driven) {
  return fmt::format("\x01{}\x01{}\x01{}", kind, chain, driven);
}

std::size_t NetworkBuilder::scope_of(const std::string& flat) const {
  auto it = c_.node_scope.find(flat);
  return it == c_.node_scope.end() ? 0 : it->second;
}

Network NetworkBuilder::build() {
  net_.format = "SPICE";
  net_.model = c_.files.empty() ? "netlist" : model_name(c_.files.front(), "netlist");
  std::string files;
  for (const auto& f : c_.files)
    files += (files.empty() ? "" : ", ") + lang::escape_for_display(f);
  net_.heading.push_back("SPICE netlist imported by `thermnet import`: " + files);
  if (!c_.title.empty()) net_.heading.push_back("Title: " + lang::escape_for_display(c_.title));
  sources_v();
  check_elements();
  const auto held = [this](const std::string& n) { return n == "0" || held_.count(n) > 0; };
  std::set<std::string> with_ic;
  for (const auto& ic : c_.ics)
    with_ic.insert(ic.node);
  chains_ = find_foster_chains(c_.elements, usable_, held, with_ic, report_);
  for (const auto& ch : chains_)
    for (std::size_t i : ch.consumed)
      usable_[i] = false;
  if (report_.error_count() > 0) return std::move(net_);
  capacities();
  declare_nodes();
  initial_conditions();
  resistors();
  cauer_ladders();
  heaters();
  case_spec();
  net_.heading.push_back(
      std::string("Units: a volt is a degree Celsius, an ampere a watt, an ohm a K/W, a farad a "
                  "J/K") +
      (ground_used_ ? "; SPICE's node 0 is the boundary gnd, at 0 degC" : ""));
  if (ground_used_)
    net_.boundaries.insert(
        net_.boundaries.begin(),
        Boundary{Name{"0", {}}, {temperature(0), {}}, "SPICE node 0", first_ground_});
  return std::move(net_);
}

/// V sources from a node to ground: boundaries.
void NetworkBuilder::sources_v() {
  for (std::size_t i = 0; i < c_.elements.size(); ++i) {
    const Element& e = c_.elements[i];
    if (e.kind != 'v') continue;
    usable_[i] = false;
    if (e.a == e.b || (e.a == "0" && e.b == "0")) {
      report_.error(
          e.at, "self-link",
          fmt::format("V source '{}' connects node {} to itself", shown(e.name), shown(e.a)));
      continue;
    }
    if (e.a != "0" && e.b != "0") {
      report_.dropped(e.at, fmt::format("V source '{}' between two nodes ({} and {}): thermnet "
                                        "holds a node's temperature, not a difference",
                                        shown(e.name), shown(e.a), shown(e.b)));
      continue;
    }
    const std::string& node = e.b == "0" ? e.a : e.b;
    const double sign = e.b == "0" ? 1.0 : -1.0;
    if (auto it = held_.find(node); it != held_.end()) {
      report_.error(e.at, "duplicate-name",
                    fmt::format("node {} is held by two V sources", shown(node)),
                    {{c_.elements[it->second].at, "the other source"}});
      continue;
    }
    held_[node] = i;
    held_signal_[node] = signal_of(e, sign, true);
    if (e.scope != scope_of(node)) {
      held_signal_[node].constant.scoped.clear();
      for (auto& [t, v] : held_signal_[node].points) {
        t.scoped.clear();
        v.scoped.clear();
      }
    }
  }
}

/// Values that cannot be written; elements that change no temperature.
void NetworkBuilder::check_elements() {
  for (std::size_t i = 0; i < c_.elements.size(); ++i) {
    const Element& e = c_.elements[i];
    if (!usable_[i]) continue;
    const bool ground_a = e.a == "0", ground_b = e.b == "0";
    const auto fixed = [&](const std::string& n) { return n == "0" || held_.count(n) > 0; };
    if (e.kind == 'i') {
      if (e.a == e.b) {
        report_.note(e.at, fmt::format("current source '{}' runs from a node to itself and "
                                       "changes no temperature: not written",
                                       shown(e.name)));
        usable_[i] = false;
      }
      continue;
    }
    if (e.a == e.b || (ground_a && ground_b)) {
      report_.error(e.at, "self-link",
                    fmt::format("'{}' connects node {} to itself", shown(e.name), shown(e.a)));
      usable_[i] = false;
      continue;
    }
    const char* what = e.kind == 'r' ? "resistance" : "capacitance";
    if (e.value < 0 || (e.kind == 'r' && e.value == 0)) {
      report_.error(e.value_at, "invalid-value",
                    e.value == 0 ? fmt::format("'{}' has a resistance of 0 (a short): thermnet "
                                               "needs R > 0 (join the two nodes instead)",
                                               shown(e.name))
                                 : fmt::format("'{}' has a negative {} ({})", shown(e.name), what,
                                               number_text(e.value)));
      usable_[i] = false;
      continue;
    }
    if (e.kind == 'c' && e.value == 0) {
      report_.note(e.at, fmt::format("capacitor '{}' is 0: not written", shown(e.name)));
      usable_[i] = false;
      continue;
    }
    if (fixed(e.a) && fixed(e.b)) {
      report_.note(e.at, fmt::format("'{}' joins two held nodes ({} and {}) and changes no "
                                     "temperature: not written",
                                     shown(e.name), shown(e.a), shown(e.b)));
      usable_[i] = false;
      continue;
    }
    if (e.kind == 'c' && (ground_a || ground_b) && fixed(ground_a ? e.b : e.a)) {
      report_.note(e.at, fmt::format("capacitor '{}' is on node {}, which a V source holds: "
                                     "not written",
                                     shown(e.name), shown(ground_a ? e.b : e.a)));
      usable_[i] = false;
    }
  }
}

void NetworkBuilder::capacities() {
  const bool uic = c_.tran && c_.tran->uic;
  for (std::size_t i = 0; i < c_.elements.size(); ++i) {
    const Element& e = c_.elements[i];
    if (!usable_[i] || e.kind != 'c') continue;
    const std::string& node = e.a == "0" ? e.b : e.a;
    cap_[node] += e.value;
    cap_at_.emplace(node, e.at);
    ++cap_count_[node];
    if (e.scope != scope_of(node)) cap_from_.emplace(node, e.name);
    if (e.expr && e.scope == scope_of(node)) cap_expr_[node] = *e.expr;
    if (e.ic) {
      if (!uic) {
        report_.note(e.at, fmt::format("ignored: IC= of '{}' (as in SPICE, it applies only "
                                       "with .tran ... UIC)",
                                       shown(e.name)));
        continue;
      }
      const double ic = e.a == "0" ? -*e.ic : *e.ic;
      if (auto it = t0_.find(node); it != t0_.end() && it->second.first != ic)
        report_.error(e.at, "duplicate-name",
                      fmt::format("node {} is given two initial conditions", shown(node)),
                      {{it->second.second, "the other one"}});
      t0_[node] = {ic, e.at};
    }
  }
}

/// Every node an element still written touches, in the netlist's order.
void NetworkBuilder::declare_nodes() {
  std::set<std::string> seen;
  const auto add = [&](const std::string& n, lang::Span at) {
    if (n == "0") {
      if (!ground_used_) first_ground_ = at;
      return;
    }
    if (!seen.insert(n).second) return;
    if (held_.count(n)) {
      const Element& v = c_.elements[held_[n]];
      net_.boundaries.push_back({Name{n, {}}, held_signal_[n],
                                 "held by " + lang::excerpt_for_display(v.name, 60), v.at,
                                 scope_of(n)});
      return;
    }
    node_index_[n] = net_.nodes.size();
    Value C = number(cap_.count(n) ? cap_[n] : 0.0);
    if (cap_count_[n] == 1 && cap_expr_.count(n)) C.scoped = cap_expr_[n];
    std::string what;
    if (auto it = cap_from_.find(n); it != cap_from_.end())
      what = "C from " + lang::excerpt_for_display(it->second, 60) +
             (cap_count_[n] > 1 ? " and others" : "");
    net_.nodes.push_back({Name{n, {}}, C, std::nullopt, what,
                          // (a node with a capacity cites the card that gives it, the others the
                          // first that names it)
                          cap_at_.count(n) ? cap_at_[n] : at, scope_of(n)});
  };
  for (std::size_t i = 0; i < c_.elements.size(); ++i) {
    const Element& e = c_.elements[i];
    if (!usable_[i] && !(e.kind == 'v' && held_.count(e.a == "0" ? e.b : e.a))) continue;
    if (e.kind == 'v') {
      add(e.a == "0" ? e.b : e.a, e.at);
      continue;
    }
    add(e.a, e.at);
    add(e.b, e.at);
    if (e.kind == 'r' && (e.a == "0" || e.b == "0")) ground_used_ = true;
  }
  for (const auto& ch : chains_) {
    if (!ch.written) continue;
    add(ch.driven, ch.at);
    add(ch.far, ch.at);
    if (ch.far == "0") ground_used_ = true;
  }
}

} // namespace detail

Network read_network(const std::vector<std::string>& paths, lang::SourceManager& sources,
                     Report& report, std::vector<std::string>& files_read,
                     const std::function<bool(const std::string&)>& is_kind) {
  Netlist netlist = read_cards(paths, sources, report);
  files_read = netlist.files;
  if (report.error_count() > 0) return {};
  Circuit circuit = flatten(std::move(netlist), sources, report);
  if (report.error_count() > 0) return {};
  detail::NetworkBuilder builder(circuit, report);
  Network flat = builder.build();
  if (report.error_count() > 0) return {};
  // (the elements are in the network now: their memory goes before the submodels are made)
  std::vector<Element>().swap(circuit.elements);
  Folded folded = fold(flat, circuit, sources, is_kind);
  // The notes that name nodes come once the model's names are known.
  builder.ladder_notes([&](const std::string& n) { return folded.name(n); });
  note_floating(flat, report, [&](const Name& n) { return folded.name(n.text()); });
  for (const auto& [at, text] : folded.notes)
    report.note(at, text);
  return std::move(folded.net);
}

} // namespace thermnet::importer::spice
