// What the hypothesis plugins share: netlist text, elements and names for their extensions, and
// the screen's regression of the unexplained heat flows on a candidate term.

#include "kernel/diagnosis/hypothesis.hpp"

#include "kernel/core/element_registry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace thermnet {

std::string netlist_number(double v) {
  return fmt::format("{:.5g}", v + 0.0); // + 0.0: no "-0"
}

std::string signal_text(const lang::Signal& s, const std::string& unit) {
  const std::string u = unit.empty() ? "" : " [" + unit + "]";
  if (s.is_constant()) return netlist_number(s.constant) + u;
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

ScreenFit Evidence::regress(
    const std::function<double(std::size_t c, int node, std::size_t k)>& basis) const {
  double qb = 0.0, bb = 0.0, qq = 0.0;
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const CaseEvidence& ce = cases[c];
    for (int node : ce.rows) {
      const double C = ce.spec.nodes[static_cast<std::size_t>(node)].C;
      for (std::size_t k = 0; k < ce.q.size(); ++k) {
        const double q = ce.q[k][static_cast<std::size_t>(node)];
        if (std::isnan(q)) continue;
        const double b = basis(c, node, k);
        if (!std::isfinite(b) || b == 0.0) {
          qq += q * q / (C * C);
          continue;
        }
        qb += q * b / (C * C);
        bb += b * b / (C * C);
        qq += q * q / (C * C);
      }
    }
  }
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
