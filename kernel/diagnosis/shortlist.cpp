// The screen's shortlist: every hypothesis proposes candidates on the evidence, and the model-side
// ones are refitted by site in the screen's order, widened per kind and per node.

#include "kernel/diagnosis/selection.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace thermnet::detail {

std::string site(const Candidate& c) {
  return fmt::format("{}|{}|{}", c.kind, fmt::join(c.nodes, ","), c.element);
}

std::vector<std::string> site_order(const std::vector<Entry>& side) {
  std::vector<std::string> order;
  std::set<std::string> seen;
  for (const auto& e : side)
    if (e.c.screen > 0 && seen.insert(site(e.c)).second) order.push_back(site(e.c));
  return order;
}

bool model_side(const Entry& e) {
  return !e.c.measurement_side && !e.own_h->recalibrates();
}

std::vector<Entry> Selection::propose(const Evidence& ev) const {
  std::vector<Entry> out;
  const auto& elements = engine_.evidence().cases.front().spec.elements;
  for (const auto& h : hyps_)
    for (auto& c : h->propose(ev)) {
      // An element added by an applied finding is not a site of the model's own.
      if (!c.element.empty() &&
          std::none_of(elements.begin(), elements.end(),
                       [&](const lang::ElementSpec& e) { return e.name == c.element; }))
        continue;
      Entry e;
      e.h = e.own_h = h.get();
      e.own = c;
      e.c = std::move(c);
      out.push_back(std::move(e));
    }
  return out;
}

Screened Selection::screen(const Evidence& ev) const {
  Screened s;
  for (auto& e : propose(ev))
    (model_side(e) ? s.side : s.others).push_back(std::move(e));
  std::stable_sort(s.side.begin(), s.side.end(),
                   [](const Entry& a, const Entry& b) { return a.c.screen > b.c.screen; });
  return s;
}

std::vector<std::size_t> Selection::shortlist(const std::vector<Entry>& side, const Evidence& ev,
                                              std::size_t sites) const {
  // `side` is sorted by falling screen score. The shortlist holds, by site: the `sites` best, the
  // best of each kind, and -- since the regression ranks sites of every node together, where a
  // node with a large unexplained flow may be out-scored by many proxies elsewhere -- the two best
  // sites of each of the three nodes with the largest unexplained heat flow.
  const std::vector<std::string> order = site_order(side);
  std::set<std::string> wanted(order.begin(),
                               order.begin() + static_cast<long>(std::min(sites, order.size())));
  std::set<std::string> kinds;
  for (const auto& e : side)
    if (e.c.screen > 0 && kinds.insert(e.c.kind).second) wanted.insert(site(e.c));
  std::map<int, double> flow; // node -> sum of (q / C)^2
  for (const auto& ce : ev.cases)
    for (int node : ce.rows) {
      const double C = ce.spec.nodes[static_cast<std::size_t>(node)].C;
      for (const auto& q : ce.q)
        if (std::isfinite(q[static_cast<std::size_t>(node)]))
          flow[node] +=
              q[static_cast<std::size_t>(node)] * q[static_cast<std::size_t>(node)] / (C * C);
    }
  std::vector<std::pair<double, int>> nodes;
  for (const auto& [node, ss] : flow)
    nodes.emplace_back(-ss, node);
  std::sort(nodes.begin(), nodes.end());
  for (std::size_t i = 0; i < nodes.size() && i < 3; ++i) {
    const std::string& name =
        ev.cases.front().spec.nodes[static_cast<std::size_t>(nodes[i].second)].name;
    std::set<std::string> of_node;
    for (const auto& e : side)
      if (e.c.screen > 0 && of_node.size() < 2 &&
          std::find(e.c.nodes.begin(), e.c.nodes.end(), name) != e.c.nodes.end())
        of_node.insert(site(e.c));
    wanted.insert(of_node.begin(), of_node.end());
  }
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < side.size(); ++i)
    if (side[i].c.screen > 0 && wanted.count(site(side[i].c)) != 0) idx.push_back(i);
  return idx;
}

std::vector<Entry> Selection::shortlisted(const std::vector<Entry>& side, const Evidence& ev,
                                          std::size_t sites, std::set<std::size_t>* taken) const {
  std::vector<Entry> fresh;
  for (std::size_t i : shortlist(side, ev, sites))
    if (!taken || taken->insert(i).second) fresh.push_back(side[i]);
  return fresh;
}

} // namespace thermnet::detail
