// Hypothesis 'missing_link': a linear (conduction, contact, convection) or radiative path between
// two nodes, or a node and a boundary, that the model lacks. Screen: the unexplained heat flow of
// each end regressed on T_b - T_a (linear) or sigma (T_b^4 - T_a^4) (radiation).
#include "kernel/diagnosis/hypothesis.hpp"

#include "kernel/core/parallel.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace thermnet {
namespace {

constexpr double kStefanBoltzmann = 5.670374419e-8;

/// The heat driving term into node `to` from node `from` for a mechanism.
double drive(bool radiative, double to, double from) {
  if (!radiative) return from - to;
  const double a2 = from * from, b2 = to * to;
  return kStefanBoltzmann * (a2 * a2 - b2 * b2);
}

class MissingLink final : public Hypothesis {
public:
  std::vector<std::string> mechanisms() const override { return {"linear", "radiation"}; }

  std::vector<Candidate> propose(const Evidence& ev) const override {
    // Every pair is screened; a 150-node network has 11,000 of them, so the first ends are spread
    // over the threads, each into its own list (the order is the pairs' whatever the threads).
    if (ev.cases.empty()) return {};
    const int n = static_cast<int>(ev.cases.front().spec.nodes.size());
    std::vector<std::vector<Candidate>> from(static_cast<std::size_t>(n));
    parallel_for(from.size(), ev.threads, [&](std::size_t a) {
      for (int b = static_cast<int>(a) + 1; b < n; ++b)
        propose_pair(ev, static_cast<int>(a), b, from[a]);
    });
    std::vector<Candidate> out;
    for (auto& list : from)
      std::move(list.begin(), list.end(), std::back_inserter(out));
    return out;
  }

  void extend(const Candidate& c, const std::vector<double>& p,
              lang::NetworkSpec& spec) const override {
    const bool rad = c.mechanism == "radiation";
    spec.elements.push_back(make_element(rad ? "radiation" : "conductance",
                                         unique_name(spec, name_of(c)), {c.index[0], c.index[1]},
                                         {{rad ? "GR" : "G", p[0]}}));
  }

  std::string statement(const Candidate& c, const std::vector<double>& p,
                        const Evidence& ev) const override {
    const bool rad = c.mechanism == "radiation";
    return fmt::format("{} {} {} {} {} = {} [{}]", rad ? "radiation" : "conductance",
                       unique_name(ev.cases.front().spec, name_of(c)), c.nodes[0], c.nodes[1],
                       rad ? "GR" : "G", netlist_number(p[0]), rad ? "m^2" : "W/K");
  }

private:
  /// The candidates of the pair (a, b), a < b, appended to `out`: both mechanisms, screened where
  /// one end is measured.
  static void propose_pair(const Evidence& ev, int a, int b, std::vector<Candidate>& out) {
    const auto& nodes = ev.cases.front().spec.nodes;
    if (nodes[static_cast<std::size_t>(a)].boundary && nodes[static_cast<std::size_t>(b)].boundary)
      return;
    if (!ev.measured(a) && !ev.measured(b)) {
      const auto free = [&](int i) {
        return ev.unobserved(i) || nodes[static_cast<std::size_t>(i)].boundary;
      };
      if (free(a) && free(b))
        for (bool rad : {false, true})
          out.push_back(unobserved(nodes, a, b, rad));
      return;
    }
    for (bool rad : {false, true}) {
      const ScreenFit f = ev.regress(
          [&](std::size_t c, int node, std::size_t k) {
            const auto& T = ev.cases[c].T[k];
            if (node == a)
              return drive(rad, T[static_cast<std::size_t>(a)], T[static_cast<std::size_t>(b)]);
            if (node == b)
              return drive(rad, T[static_cast<std::size_t>(b)], T[static_cast<std::size_t>(a)]);
            return 0.0;
          },
          {a, b});
      if (f.coefficient <= 0.0) continue; // heat would flow against the difference
      Candidate c = link(nodes, a, b, rad);
      c.start = {std::clamp(f.coefficient, c.lo[0] * 10, c.hi[0] / 10)};
      c.screen = f.reduction;
      c.evidence = fmt::format(
          "the unexplained heat flow of {} and {} follows {} (correlation {:.2f})", c.nodes[0],
          c.nodes[1], rad ? "the difference of T^4" : "their temperature difference",
          f.correlation);
      out.push_back(std::move(c));
    }
  }
  /// A link between nodes a and b by one mechanism, its parameter and bounds (no start yet).
  static Candidate link(const std::vector<lang::NodeSpec>& nodes, int a, int b, bool rad) {
    Candidate c;
    c.kind = "missing_link";
    c.nodes = {nodes[static_cast<std::size_t>(a)].name, nodes[static_cast<std::size_t>(b)].name};
    c.mechanism = rad ? "radiation" : "linear";
    c.names = {rad ? "GR" : "G"};
    c.lo = {rad ? 1e-8 : 1e-6};
    c.hi = {rad ? 100.0 : 1e4};
    c.index = {a, b};
    return c;
  }
  /// A link between two unmeasured nodes: refitted only beside a shortlisted link of a measured
  /// neighbour.
  static Candidate unobserved(const std::vector<lang::NodeSpec>& nodes, int a, int b, bool rad) {
    Candidate c = link(nodes, a, b, rad);
    c.start = {rad ? 1e-3 : 0.1};
    c.unobserved = true;
    c.evidence = fmt::format("{} and {} are not measured; a path between them shows at their "
                             "measured neighbours",
                             c.nodes[0], c.nodes[1]);
    return c;
  }
  static std::string name_of(const Candidate& c) {
    return fmt::format("diag_{}_{}", c.nodes[0], c.nodes[1]);
  }
};

HypothesisPlugin make_missing_link() {
  return {.name = "missing_link",
          .doc = "a linear or radiative path between two nodes (or a node and a boundary)",
          .create = [] { return std::make_unique<MissingLink>(); },
          .screen = "T_b - T_a, or sigma (T_b^4 - T_a^4), at both ends",
          .fitted = "G [W/K] (linear) or GR [m^2] (radiation)",
          .writes = "conductance diag_a_b a b G = ..., or radiation diag_a_b a b GR = ..."};
}

} // namespace
THERMNET_REGISTER(HypothesisPlugin, make_missing_link);
} // namespace thermnet
