// The screen's shortlist: every hypothesis proposes candidates on the evidence, and the model-side
// ones are refitted by site in the screen's order, widened per kind and per node, and beside each
// shortlisted candidate by its counterparts on unmeasured nodes near it (which the screen cannot
// score), and every unobserved candidate of a kind that has few of them.

#include "kernel/diagnosis/selection.hpp"

#include "kernel/core/parallel.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <functional>
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

namespace {

/// Most counterparts on unmeasured nodes refitted beside one shortlisted candidate.
constexpr std::size_t kBeside = 6;

/// A candidate's kind, mechanism and (sorted) nodes: what a counterpart on other nodes shares.
std::string shape_key(const std::string& kind, const std::string& mechanism,
                      std::vector<std::string> nodes) {
  std::sort(nodes.begin(), nodes.end());
  return fmt::format("{}|{}|{}", kind, mechanism, fmt::join(nodes, ","));
}

/// Entries by shape_key (with their mechanism, or without it) -> their indices, in order.
using Shapes = std::map<std::string, std::vector<std::size_t>>;
Shapes shapes(const std::vector<Entry>& entries, bool with_mechanism) {
  Shapes out;
  for (std::size_t j = 0; j < entries.size(); ++j)
    out[shape_key(entries[j].c.kind, with_mechanism ? entries[j].c.mechanism : "",
                  entries[j].c.nodes)]
        .push_back(j);
  return out;
}

/// Spec node -> the nodes an element links it to, in index order.
std::vector<std::set<int>> neighbours(const lang::NetworkSpec& spec) {
  std::vector<std::set<int>> out(spec.nodes.size());
  for (const auto& e : spec.elements)
    for (int a : e.nodes())
      for (int b : e.nodes())
        if (a != b) out[static_cast<std::size_t>(a)].insert(b);
  return out;
}

/// The unmeasured nodes within two links of `node` through unmeasured nodes only (its unmeasured
/// neighbours first, then theirs): where an effect there shows first.
std::vector<int> unmeasured_near(const std::vector<std::set<int>>& near, const Evidence& ev,
                                 int node) {
  std::vector<int> ring;
  for (int u : near[static_cast<std::size_t>(node)])
    if (ev.unobserved(u)) ring.push_back(u);
  const std::size_t first = ring.size();
  for (std::size_t i = 0; i < first; ++i)
    for (int w : near[static_cast<std::size_t>(ring[i])])
      if (w != node && ev.unobserved(w) && std::find(ring.begin(), ring.end(), w) == ring.end())
        ring.push_back(w);
  return ring;
}

/// The boundaries an element links the unmeasured `node` to: the screen knows an unmeasured
/// node's temperature only from the simulation, and a boundary tightly coupled to it runs at
/// nearly that temperature, so a candidate naming the node cannot be told by the screen from one
/// naming the boundary. (Unmeasured nodes are reached from the measured side, unmeasured_near:
/// exchanging them here too multiplied a 150-node diagnosis's refits by 1.7.)
std::vector<int> boundaries_near(const std::vector<std::set<int>>& near,
                                 const lang::NetworkSpec& spec, int node) {
  std::vector<int> out;
  for (int u : near[static_cast<std::size_t>(node)])
    if (spec.nodes[static_cast<std::size_t>(u)].boundary) out.push_back(u);
  return out;
}

/// For each shortlisted candidate (`picked`, indices into `side`): the candidates of its kind and
/// mechanism that name, in place of one of its measured nodes, an unmeasured node near it
/// (unmeasured_near), or in place of one of its unmeasured nodes, a boundary linked to it
/// (boundaries_near). Where an effect sits on an unmeasured node, the screen can
/// only see it through the measured nodes nearby, and their candidate is its proxy. Pairs
/// (counterpart, picked).
std::vector<std::pair<std::size_t, std::size_t>>
counterparts(const std::vector<Entry>& side, const Evidence& ev,
             const std::vector<std::size_t>& picked) {
  const Shapes by_shape = shapes(side, true);
  const auto& spec = ev.cases.front().spec;
  const auto near = neighbours(spec);
  std::vector<std::pair<std::size_t, std::size_t>> out;
  // (index, its shortlisted root, depth): a counterpart's own unmeasured ends are exchanged once
  // more for the boundaries they are tied to (a link found to an unmeasured node beside a measured
  // proxy may really go to the boundary that node is tied to).
  struct Todo {
    std::size_t i, root;
    int depth;
  };
  std::vector<Todo> todo;
  std::set<std::size_t> seen(picked.begin(), picked.end());
  for (std::size_t i : picked)
    todo.push_back({i, i, 0});
  for (std::size_t t = 0; t < todo.size(); ++t) {
    const auto [i, root, depth] = todo[t];
    const Candidate& c = side[i].c;
    std::size_t found = 0;
    for (std::size_t n = 0; n < c.nodes.size() && found < kBeside; ++n) {
      const int node = spec.node_index(c.nodes[n]);
      if (node < 0 || spec.nodes[static_cast<std::size_t>(node)].boundary) continue;
      if (depth > 0 && ev.measured(node)) continue;
      for (int u : ev.measured(node) ? unmeasured_near(near, ev, node)
                                     : boundaries_near(near, spec, node)) {
        std::vector<std::string> nodes = c.nodes;
        nodes[n] = spec.nodes[static_cast<std::size_t>(u)].name;
        auto it = by_shape.find(shape_key(c.kind, c.mechanism, nodes));
        if (it == by_shape.end()) continue;
        for (std::size_t j : it->second)
          if (found < kBeside && seen.insert(j).second) {
            out.emplace_back(j, root);
            ++found;
            if (depth == 0) todo.push_back({j, root, 1});
          }
      }
    }
  }
  return out;
}

/// The `most` measured nodes with the largest temperature error (measured - simulated, summed
/// over every case), largest first.
std::vector<std::string> largest_error_nodes(const Evidence& ev, std::size_t most) {
  std::map<std::string, double> ss;
  for (const auto& ce : ev.cases)
    for (std::size_t s = 0; s < ce.measured.series.size(); ++s) {
      const auto& m = ce.measured.series[s].values;
      for (std::size_t k = 0; k < m.size() && k < ce.simulated[s].size(); ++k)
        if (std::isfinite(m[k])) {
          const double d = m[k] - ce.simulated[s][k];
          ss[ce.measured.series[s].node] += d * d;
        }
    }
  std::vector<std::pair<double, std::string>> by_error;
  for (const auto& [name, v] : ss)
    by_error.emplace_back(-v, name);
  std::sort(by_error.begin(), by_error.end());
  std::vector<std::string> out;
  for (std::size_t i = 0; i < by_error.size() && i < most; ++i)
    out.push_back(by_error[i].second);
  return out;
}

/// Indices into `side` of every unobserved candidate of each kind that has at most `most` of them
/// (one per heater): refitted without a screen score.
std::vector<std::size_t> few_unobserved(const std::vector<Entry>& side, std::size_t most) {
  // The screen cannot score a candidate on unmeasured nodes, and the counterparts (step 4) reach
  // one only beside a shortlisted candidate of its kind on a measured node nearby. A kind whose
  // unobserved candidates are few (one per heater: heater_gain, heater_mass) needs no screen to
  // keep its refits affordable, so all of them are refitted: a heater on an unmeasured node is
  // otherwise reached only when another heater's candidate happens to sit near it.
  std::map<std::string, std::vector<std::size_t>> by_kind;
  for (std::size_t i = 0; i < side.size(); ++i)
    if (side[i].c.unobserved) by_kind[side[i].c.kind].push_back(i);
  std::vector<std::size_t> out;
  for (const auto& [kind, idx] : by_kind)
    if (idx.size() <= most) out.insert(out.end(), idx.begin(), idx.end());
  std::sort(out.begin(), out.end());
  return out;
}

/// Indices of the candidates (`by_site`: shapes with `mechanism`, or without one when it is
/// empty) of c's kind whose nodes are c's with the one at position n replaced by each of `by`, in
/// the order of `by`; at most `most` distinct replacements.
std::vector<std::size_t> exchanged(const Shapes& by_site, const lang::NetworkSpec& spec,
                                   const Candidate& c, const std::string& mechanism, std::size_t n,
                                   const std::vector<int>& by, std::size_t most) {
  std::vector<std::size_t> out;
  std::size_t found = 0;
  for (int u : by) {
    if (found >= most) break;
    std::vector<std::string> nodes = c.nodes;
    nodes[n] = spec.nodes[static_cast<std::size_t>(u)].name;
    auto it = by_site.find(shape_key(c.kind, mechanism, nodes));
    if (it == by_site.end()) continue;
    out.insert(out.end(), it->second.begin(), it->second.end());
    ++found;
  }
  return out;
}

/// Spec node -> the nodes an element links it to (neighbours).
using Near = std::vector<std::set<int>>;

/// The nodes (not boundaries) an element links `node` to, the measured ones first.
std::vector<int> nodes_near(const Near& near, const Evidence& ev, int node) {
  const auto& spec = ev.cases.front().spec;
  std::vector<int> out;
  for (int u : near[static_cast<std::size_t>(node)])
    if (!spec.nodes[static_cast<std::size_t>(u)].boundary) out.push_back(u);
  std::stable_partition(out.begin(), out.end(), [&](int u) { return ev.measured(u); });
  return out;
}

/// For each node of c, the candidates exchanged (`exchanged`) for the nodes by(near, node) lists:
/// of either mechanism, or of c's own with `same_mechanism`.
std::vector<std::size_t> exchanges(const std::vector<Entry>& entries, const Evidence& ev,
                                   const Candidate& c,
                                   const std::function<std::vector<int>(const Near&, int)>& by,
                                   bool same_mechanism = false) {
  const auto& spec = ev.cases.front().spec;
  const Near near = neighbours(spec);
  const Shapes by_site = shapes(entries, same_mechanism);
  const std::string mechanism = same_mechanism ? c.mechanism : "";
  std::vector<std::size_t> out;
  for (std::size_t n = 0; n < c.nodes.size(); ++n) {
    const int node = spec.node_index(c.nodes[n]);
    if (node < 0) continue;
    const auto more = exchanged(by_site, spec, c, mechanism, n, by(near, node), kBeside);
    out.insert(out.end(), more.begin(), more.end());
  }
  return out;
}

} // namespace

std::vector<std::size_t> boundary_exchanges(const std::vector<Entry>& entries, const Evidence& ev,
                                            const Candidate& c) {
  return exchanges(entries, ev, c, [&](const Near& near, int node) {
    return ev.unobserved(node) ? boundaries_near(near, ev.cases.front().spec, node)
                               : std::vector<int>{};
  });
}

std::vector<std::size_t> tied_node_exchanges(const std::vector<Entry>& entries, const Evidence& ev,
                                             const Candidate& c) {
  const auto& spec = ev.cases.front().spec;
  return exchanges(entries, ev, c, [&](const Near& near, int node) {
    return spec.nodes[static_cast<std::size_t>(node)].boundary ? nodes_near(near, ev, node)
                                                               : std::vector<int>{};
  });
}

bool model_side(const Entry& e) {
  return !e.c.measurement_side && !e.own_h->recalibrates();
}

std::vector<Entry> Selection::propose(const Evidence& ev) const {
  // The hypotheses screen at the same time, each into its own list (read in their order).
  std::vector<std::vector<Candidate>> proposed(hyps_.size());
  parallel_for(hyps_.size(), opt_.threads,
               [&](std::size_t i) { proposed[i] = hyps_[i]->propose(ev); });
  std::vector<Entry> out;
  const auto& declared = engine_.evidence().cases.front().spec;
  for (std::size_t i = 0; i < hyps_.size(); ++i)
    for (auto& c : proposed[i]) {
      // An element or node added by an applied finding (a heater's own mass) is not a site of
      // the model's own; but a share of a measured input may heat a node a finding added (the sun
      // onto the envelope a wall_mass added, as the published building structures have it).
      if (!on_model_sites(c, declared,
                          hyps_[i]->reroutes() ? AddedNodes::allowed : AddedNodes::refused))
        continue;
      if (!c.start_T.empty()) c = with_start_share(c);
      Entry e;
      e.h = e.own_h = hyps_[i].get();
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
  // The screen weighs heat flows per unit capacity, so a slow node (large C, weak links) whose
  // small unexplained flow builds up the largest temperature error ranks low by flow; the three
  // nodes with the largest temperature error keep the best site of each kind naming them.
  for (const std::string& name : largest_error_nodes(ev, 3)) {
    std::set<std::string> kinds_of_node;
    for (const auto& e : side)
      if (e.c.screen > 0 &&
          std::find(e.c.nodes.begin(), e.c.nodes.end(), name) != e.c.nodes.end() &&
          kinds_of_node.insert(e.c.kind).second)
        wanted.insert(site(e.c));
  }
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < side.size(); ++i)
    if (side[i].c.screen > 0 && wanted.count(site(side[i].c)) != 0) idx.push_back(i);
  return idx;
}

std::vector<Entry> Selection::shortlisted(const std::vector<Entry>& side, const Evidence& ev,
                                          std::size_t sites, std::set<std::size_t>* taken) const {
  std::set<std::size_t> local;
  if (!taken) taken = &local;
  std::vector<Entry> fresh;
  const std::vector<std::size_t> picked = shortlist(side, ev, sites);
  for (std::size_t i : picked)
    if (taken->insert(i).second) fresh.push_back(side[i]);
  const std::vector<std::size_t> few = few_unobserved(side, opt_.refits); // sorted
  for (const auto& [j, seed] : counterparts(side, ev, picked)) {
    if (!taken->insert(j).second) continue;
    Entry e = side[j];
    if (e.c.unobserved) // no screen estimate of its own: start where its measured proxy starts
      for (std::size_t k = 0; k < e.c.start.size() && k < side[seed].c.start.size(); ++k)
        e.c.start[k] = std::clamp(side[seed].c.start[k], e.c.lo[k], e.c.hi[k]);
    e.own.start = e.c.start;
    // (one of a kind's few unobserved candidates is refitted whatever its proxy gives: below)
    if (!std::binary_search(few.begin(), few.end(), j)) e.proxy = site(side[seed].c);
    fresh.push_back(std::move(e));
  }
  for (std::size_t i : few)
    if (taken->insert(i).second) fresh.push_back(side[i]);
  return fresh;
}

std::vector<std::size_t> beside_gaining(const std::vector<Entry>& entries,
                                        const std::vector<std::size_t>& beside,
                                        const std::vector<Evaluated>& res,
                                        const std::vector<std::size_t>& refitted,
                                        double reference_bic, std::size_t best) {
  // A counterpart on unmeasured nodes stands for an effect the screen sees only through the
  // measured nodes near it, where its proxy sits: refitted, the proxy takes up part of such an
  // effect. A proxy that does not beat its reference by the information criterion (as a finding
  // must) shows no effect there to look for beside it, and its counterparts are not refitted (S19
  // of the scenario table: 73 of 389 in the joint refits, and a quarter of their simulations).
  // Where one effect shows through many measured nodes, nearly every proxy gains (S19: a missing
  // link that most of the plate's candidates take up in part), and the effect lies beside the
  // proxies that take up most of it: only the `best` sites of each kind by RMSE among the gaining
  // proxies keep their counterparts (S19's joint refits: 409 -> 239). A proxy whose fit failed
  // keeps its counterparts, and so does one not refitted here (which the shortlists as built do
  // not make).
  // (a joint refit's candidate keeps its inner one's kind, nodes and element: the same site)
  std::set<std::string> gaining, known;
  std::map<std::string, std::vector<std::pair<double, std::string>>> by_kind; // (RMSE, site)
  for (std::size_t i : refitted) {
    const Finding& f = res[i].f;
    known.insert(site(entries[i].c));
    if (f.values.empty())
      gaining.insert(site(entries[i].c));
    else if (f.delta_bic - reference_bic < kSignificantBic)
      by_kind[entries[i].c.kind].emplace_back(f.rmse_after, site(entries[i].c));
  }
  for (auto& [kind, proxies] : by_kind) {
    std::sort(proxies.begin(), proxies.end());
    std::set<std::string> kept;
    for (const auto& [rmse, s] : proxies)
      if (kept.size() < best) kept.insert(s);
    gaining.insert(kept.begin(), kept.end());
  }
  std::vector<std::size_t> out;
  for (std::size_t i : beside)
    if (gaining.count(entries[i].proxy) != 0 || known.count(entries[i].proxy) == 0)
      out.push_back(i);
  return out;
}

std::vector<std::size_t> neighbour_exchanges(const std::vector<Entry>& entries, const Evidence& ev,
                                             const Candidate& c) {
  // A path the model lacks shows as unexplained heat at both its ends, and at the nodes tied
  // closely to them; the screen may rank a pair with one end's neighbour first (a box linked to
  // the panel cell under the other box: bench/panel_hit_rate.py's misses).
  if (c.kind != "missing_link" || c.nodes.size() != 2) return {};
  const auto& spec = ev.cases.front().spec;
  return exchanges(
      entries, ev, c,
      [&](const Near& near, int node) {
        return spec.nodes[static_cast<std::size_t>(node)].boundary ? std::vector<int>{}
                                                                   : nodes_near(near, ev, node);
      },
      true);
}

} // namespace thermnet::detail
