// What the hypothesis plugins share: netlist text, elements and names for their extensions, and
// the screen's regression of the unexplained heat flows on a candidate term.

#include "kernel/diagnosis/hypothesis.hpp"

#include "kernel/core/element_registry.hpp"
#include "lang/units.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

namespace thermnet {

std::string netlist_number(double v) {
  return fmt::format("{:.5g}", v + 0.0); // + 0.0: no "-0"
}

std::string signal_text(const lang::Signal& s, const std::string& unit) {
  const std::string u = unit.empty() ? "" : " [" + unit + "]";
  if (s.is_constant()) return netlist_number(s.constant) + u;
  if (s.kind() == lang::Signal::Kind::expression) // no netlist text: read it by name instead
    throw std::logic_error("signal_text: an expression has no constant, step or pwl text");
  std::string out = s.kind() == lang::Signal::Kind::step ? "step(" : "pwl(";
  for (std::size_t i = 0; i < s.times().size(); ++i)
    out += fmt::format("{}{}: {}{}", i ? ", " : "", s.times()[i], netlist_number(s.values()[i]), u);
  return out + ")";
}

bool same_signal(const lang::Signal& a, const lang::Signal& b) {
  return a.same_as(b);
}

std::vector<int> named_heaters(const lang::NetworkSpec& spec) {
  std::vector<int> out;
  for (std::size_t e = 0; e < spec.elements.size(); ++e) {
    const auto& el = spec.elements[e];
    if (el.kind() == "heater" && el.has("P") && !el.name.empty() &&
        !spec.nodes.at(static_cast<std::size_t>(el.nodes()[0])).boundary)
      out.push_back(static_cast<int>(e));
  }
  return out;
}

const lang::Signal& heater_power(const DeclaredSpec& d, const std::string& element) {
  for (const auto& el : d.spec.elements)
    if (el.name == element && el.has("P")) return el.values.at("P");
  throw std::logic_error("no heater '" + element + "' with a power in the declared network");
}

void merge_case_lines(CaseLines& lines, const CaseLines& more) {
  for (const auto& [name, text] : more) {
    std::string& to = lines[name];
    to += (to.empty() ? "" : "\n") + text;
  }
}

lang::ElementSpec make_element(const std::string& kind, const std::string& name,
                               std::vector<int> nodes, const std::map<std::string, double>& keys) {
  lang::ElementSpec e;
  e.schema = element_catalog().find(kind);
  if (!e.schema) throw std::invalid_argument("no element kind '" + kind + "'");
  e.name = name;
  e.set_nodes(nodes);
  for (const auto& [k, v] : keys)
    e.set(k, lang::Signal::of(v));
  return e;
}

std::string unique_name(const lang::NetworkSpec& spec, const std::string& base) {
  auto taken = [&](const std::string& n) {
    if (spec.node_index(n) >= 0) return true;
    for (const auto& e : spec.elements)
      if (e.name == n) return true;
    return false;
  };
  std::string n = base;
  for (int i = 2; taken(n); ++i)
    n = fmt::format("{}_{}", base, i);
  return n;
}

std::string unique_model_name(const Evidence& ev, const std::string& base) {
  std::set<std::string> params;
  if (ev.model)
    for (const auto& p : ev.model->params())
      params.insert(p.name);
  std::string n = unique_name(ev.declared.spec, base);
  for (int i = 2; params.count(n) != 0; ++i)
    n = unique_name(ev.declared.spec, fmt::format("{}_{}", base, i));
  return n;
}

double sampling_interval(const Evidence& ev) {
  std::vector<double> dt;
  for (const auto& ce : ev.cases)
    for (std::size_t k = 1; k < ce.times().size(); ++k)
      dt.push_back(ce.times()[k] - ce.times()[k - 1]);
  if (dt.empty()) return 0.0;
  std::nth_element(dt.begin(), dt.begin() + static_cast<long>(dt.size() / 2), dt.end());
  return dt[dt.size() / 2];
}

double longest_span(const Evidence& ev) {
  double span = 0.0;
  for (const auto& ce : ev.cases)
    if (!ce.times().empty()) span = std::max(span, ce.times().back() - ce.times().front());
  return span;
}

std::vector<std::vector<double>> mass_restarts(const Candidate& c, std::size_t k) {
  std::vector<std::vector<double>> out;
  if (c.start.size() < k + 2) return out;
  for (auto [j, factor] : {std::pair{k + 1, 4.0}, {k + 1, 0.25}, {k, 4.0}, {k, 0.25}}) {
    std::vector<double> s = c.start;
    s[j] = std::clamp(s[j] * factor, c.lo[j], c.hi[j]);
    if (s[j] != c.start[j]) out.push_back(std::move(s));
  }
  return out;
}

std::vector<double> screen_taus(const Evidence& ev) {
  std::vector<double> out;
  const double dt = sampling_interval(ev), span = longest_span(ev);
  for (double tau = 3.0 * dt; dt > 0.0 && tau <= 0.5 * span; tau *= 2.0)
    out.push_back(tau);
  return out;
}

std::vector<double> lowpass(const std::vector<double>& times, const std::vector<double>& u,
                            double tau, double y0) {
  std::vector<double> y(u.size());
  if (u.empty()) return y;
  y[0] = y0;
  for (std::size_t k = 1; k < u.size(); ++k) {
    const double h = times[k] - times[k - 1];
    if (!(h > 0.0)) {
      y[k] = y[k - 1];
      continue;
    }
    const double E = std::exp(-h / tau), slope = (u[k] - u[k - 1]) / h;
    y[k] = u[k] - slope * tau + (y[k - 1] - u[k - 1] + slope * tau) * E;
  }
  return y;
}

std::map<std::string, double> start_temperatures(const Evidence& ev, int node) {
  std::map<std::string, double> out;
  for (const auto& ce : ev.cases)
    if (!ce.T.empty()) out[ce.name] = ce.T.at(0, static_cast<std::size_t>(node));
  return out;
}

std::optional<double> steady_start(const lang::NetworkSpec& spec, int node,
                                   const std::map<int, double>& known) {
  const auto start_of = [&](int i) {
    if (auto it = known.find(i); it != known.end()) return it->second;
    const lang::NodeSpec& n = spec.nodes.at(static_cast<std::size_t>(i));
    if (n.boundary) return n.T.at(0.0);
    return n.T0 ? *n.T0 : spec.default_initial();
  };
  double g_sum = 0.0, flow = 0.0;
  for (const auto& e : spec.elements) {
    const auto nodes = e.nodes();
    if (std::find(nodes.begin(), nodes.end(), node) == nodes.end() || !e.schema) continue;
    if (e.schema->kind == "heater" && nodes.size() == 1 && e.has("P")) {
      flow += e.values.at("P").at(0.0);
      continue;
    }
    if (!e.schema->conductance || nodes.size() != 2 || e.composite() != lang::Composite::none)
      continue;
    bool constant = true;
    for (const auto& [k, v] : e.values)
      constant = constant && v.is_constant();
    if (!constant) continue;
    const double G = e.schema->conductance(e.key_values());
    if (!(std::isfinite(G) && G > 0.0)) continue;
    const int other = nodes[0] == node ? nodes[1] : nodes[0];
    g_sum += G;
    flow += G * start_of(other);
  }
  if (!(g_sum > 0.0)) return std::nullopt;
  const double T = flow / g_sum;
  return std::isfinite(T) && T > 0.0 ? std::optional<double>(T) : std::nullopt;
}

bool on_model_sites(const Candidate& c, const lang::NetworkSpec& declared, AddedNodes nodes) {
  if (!c.element.empty() &&
      std::none_of(declared.elements.begin(), declared.elements.end(),
                   [&](const lang::ElementSpec& e) { return e.name == c.element; }))
    return false;
  return nodes == AddedNodes::allowed ||
         std::all_of(c.nodes.begin(), c.nodes.end(),
                     [&](const std::string& n) { return declared.node_index(n) >= 0; });
}

Candidate with_start_share(const Candidate& c) {
  Candidate out = c;
  out.names.emplace_back(kStartShare);
  out.start.push_back(0.0);
  out.lo.push_back(0.0);
  out.hi.push_back(1.0);
  return out;
}

std::optional<double> start_share(const Candidate& c, const std::vector<double>& p) {
  for (std::size_t j = 0; j < c.names.size() && j < p.size(); ++j)
    if (c.names[j] == kStartShare) return std::clamp(p[j], 0.0, 1.0);
  return std::nullopt;
}

std::vector<std::vector<double>> start_restarts(const Candidate& c) {
  for (std::size_t j = 0; j < c.names.size() && j < c.start.size(); ++j)
    if (c.names[j] == kStartShare) {
      std::vector<double> s = c.start;
      s[j] = s[j] < 0.5 ? 1.0 : 0.0;
      return {s};
    }
  return {};
}

void place_start(const Candidate& c, const std::vector<double>& p, lang::NetworkSpec& spec,
                 int mass, int anchor) {
  std::map<int, double> known;
  if (auto it = c.start_T.find(spec.settings.name); it != c.start_T.end())
    known[anchor] = it->second;
  const std::optional<double> own = known.count(anchor)
                                        ? std::optional<double>(known[anchor])
                                        : spec.nodes.at(static_cast<std::size_t>(anchor)).T0;
  std::optional<double> T0 = steady_start(spec, mass, known);
  if (!T0) T0 = own;
  if (const auto share = start_share(c, p); share && T0 && own)
    *T0 = (1.0 - *share) * *T0 + *share * *own;
  spec.nodes.at(static_cast<std::size_t>(mass)).T0 = T0;
}

std::map<std::string, double> added_starts(const Hypothesis& h, const Candidate& c,
                                           const std::vector<double>& p, const Evidence& ev) {
  std::map<std::string, double> out;
  for (const auto& ce : ev.cases) {
    try {
      lang::NetworkSpec spec = ce.spec;
      const std::size_t before = spec.nodes.size();
      h.extend(c, p, spec);
      if (spec.nodes.size() > before && spec.nodes.back().T0) out[ce.name] = *spec.nodes.back().T0;
    } catch (const std::exception&) {
      return {};
    }
  }
  return out;
}

std::string start_words(const Candidate& c, const std::vector<double>& p) {
  const auto share = start_share(c, p);
  if (!share || *share < 0.005) return "starts at the steady state around it at the first sample";
  if (*share > 0.995)
    return "starts at the temperature of the node it hangs off at the first sample";
  return fmt::format("starts {:.0f} % of the way from the steady state around it to the "
                     "temperature of the node it hangs off at the first sample",
                     100.0 * *share);
}

namespace {
/// The start written at the node's declaration: that of the first case (by name), K.
std::optional<double> first_start(const std::map<std::string, double>& starts) {
  if (starts.empty()) return std::nullopt;
  return starts.begin()->second;
}
} // namespace

std::string start_text(const std::map<std::string, double>& starts) {
  const auto t = first_start(starts);
  return t ? " T0 = " + netlist_number(*t - lang::kZeroCelsius) : "";
}

CaseLines start_case_lines(const std::map<std::string, double>& starts, const std::string& node,
                           const Evidence& ev) {
  CaseLines out;
  const auto first = first_start(starts);
  if (!first) return out;
  const std::string declared = netlist_number(*first - lang::kZeroCelsius);
  for (const auto& d : ev.declared_cases) {
    auto it = starts.find(d.case_name);
    if (it == starts.end()) continue;
    const std::string t0 = netlist_number(it->second - lang::kZeroCelsius);
    if (t0 != declared) out[d.case_name] = fmt::format("{}.T0 = {}", node, t0);
  }
  return out;
}

bool on_bound(const Candidate& c, const std::vector<double>& p, std::size_t j, bool upper) {
  if (j >= p.size() || j >= c.lo.size() || !(c.hi[j] > c.lo[j])) return false;
  const double bound = upper ? c.hi[j] : c.lo[j];
  if (c.lo[j] > 0.0 && p[j] > 0.0)
    return std::abs(std::log(p[j] / bound)) <= 1e-3 * std::log(c.hi[j] / c.lo[j]);
  return std::abs(p[j] - bound) <= 1e-3 * (c.hi[j] - c.lo[j]);
}

int add_node(lang::NetworkSpec& spec, const std::string& base, double C, std::optional<double> T0,
             const std::string& doc) {
  lang::NodeSpec m;
  m.name = unique_name(spec, base);
  m.C = C;
  m.T0 = T0;
  m.set_doc(doc);
  spec.nodes.push_back(std::move(m));
  return static_cast<int>(spec.nodes.size()) - 1;
}

int add_tied_mass(lang::NetworkSpec& spec, const std::string& base, double C,
                  std::optional<double> T0, const std::string& doc, int node, double G) {
  const int mass = add_node(spec, base, C, T0, doc);
  spec.elements.push_back(
      make_element("conductance", unique_name(spec, base + "_g"), {mass, node}, {{"G", G}}));
  return mass;
}

std::string tied_mass_statements(const Evidence& ev, const Candidate& c, std::size_t k,
                                 const std::vector<double>& p, const std::string& base,
                                 const std::string& node, const std::string& doc,
                                 const std::string& start) {
  const std::string m = unique_model_name(ev, base);
  const std::string pc = unique_model_name(ev, m + "_C"), pg = unique_model_name(ev, m + "_G");
  return fmt::format("{}\n{}\nnode {} C = {}{} \"{}\"\nconductance {} {} {} G = {}",
                     param_statement(pc, p[k], c.lo[k], c.hi[k], "J/K", "capacity of the mass"),
                     param_statement(pg, p[k] / p[k + 1], c.lo[k] / c.hi[k + 1],
                                     c.hi[k] / c.lo[k + 1], "W/K", "its conductance to " + node),
                     m, pc, start, doc, unique_model_name(ev, m + "_g"), m, node, pg);
}

bool sensed(const Evidence& ev, int node) {
  for (const auto& ce : ev.cases)
    for (const auto& s : ce.measured.series)
      if (s.node_index == node) return true;
  return false;
}

std::string unscreened_words(const Evidence& ev, int node) {
  const std::string& name = ev.cases.front().spec.nodes.at(static_cast<std::size_t>(node)).name;
  return sensed(ev, node) ? fmt::format("the sensor of {} was found faulty by a finding above, "
                                        "so {} is screened with its simulated temperature",
                                        name, name)
                          : fmt::format("{} is not measured", name);
}

std::string param_statement(const std::string& name, double value, double lo, double hi,
                            const std::string& unit, const std::string& doc) {
  const std::string u = unit.empty() ? "" : " [" + unit + "]";
  return fmt::format("param {} = {}{} range {}{} .. {}{} \"{}\"", name, netlist_number(value), u,
                     netlist_number(lo), u, netlist_number(hi), u, doc);
}

void Evidence::sum_screen() {
  // (in regress()'s order of the rows: its correlations are the same numbers to the bit as when
  // it summed q itself for every candidate)
  screen_total = 0.0;
  for (const CaseEvidence& ce : cases)
    for (int node : ce.rows) {
      const double C = ce.spec.nodes[static_cast<std::size_t>(node)].C;
      for (const auto& qk : ce.q) {
        const double q = qk[static_cast<std::size_t>(node)];
        if (!std::isnan(q)) screen_total += q * q / (C * C);
      }
    }
}

ScreenFit
Evidence::regress(const std::function<double(std::size_t c, int node, std::size_t k)>& basis,
                  const std::vector<int>& support) const {
  // (only the basis's support is visited: the other rows' terms are 0, and a 72-node panel's
  // thousands of screened candidates visited every measured node and sample; the rows' sum of
  // squares is screen_total)
  double qb = 0.0, bb = 0.0;
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const CaseEvidence& ce = cases[c];
    for (int node : ce.rows) {
      if (!support.empty() && std::find(support.begin(), support.end(), node) == support.end())
        continue;
      const double C = ce.spec.nodes[static_cast<std::size_t>(node)].C;
      for (std::size_t k = 0; k < ce.q.size(); ++k) {
        const double q = ce.q[k][static_cast<std::size_t>(node)];
        if (std::isnan(q)) continue;
        const double b = basis(c, node, k);
        if (!std::isfinite(b) || b == 0.0) continue;
        qb += q * b / (C * C);
        bb += b * b / (C * C);
      }
    }
  }
  const double qq = screen_total;
  ScreenFit f;
  if (bb <= 0.0) return f;
  f.coefficient = qb / bb;
  f.reduction = qb * qb / bb;
  f.correlation = qq > 0.0 ? qb / std::sqrt(bb * qq) : 0.0;
  return f;
}

int Evidence::node_index(const std::string& name) const {
  return cases.empty() ? -1 : cases.front().spec.node_index(name);
}

bool Evidence::measured(int node) const {
  for (const auto& c : cases)
    if (std::find(c.rows.begin(), c.rows.end(), node) != c.rows.end()) return true;
  return false;
}

bool Evidence::unobserved(int node) const {
  return !measured(node) && !cases.front().spec.nodes.at(static_cast<std::size_t>(node)).boundary;
}

} // namespace thermnet
