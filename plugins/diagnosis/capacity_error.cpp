// Hypothesis 'capacity_error': a node's heat capacity is wrong by a factor. Screen: the unexplained
// heat flow regressed on -C dT/dt (its coefficient is factor - 1).
#include "kernel/diagnosis/hypothesis.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace thermnet {
namespace {

class CapacityError final : public Hypothesis {
public:
  std::vector<Candidate> propose(const Evidence& ev) const override {
    std::vector<Candidate> out;
    if (ev.cases.empty()) return out;
    const auto& nodes = ev.cases.front().spec.nodes;
    for (int a = 0; a < static_cast<int>(nodes.size()); ++a) {
      const auto& nd = nodes[static_cast<std::size_t>(a)];
      if (nd.boundary || nd.C <= 0.0) continue;
      Candidate c;
      c.kind = "capacity_error";
      c.nodes = {nd.name};
      c.names = {"factor"};
      c.lo = {0.02};
      c.hi = {50.0};
      c.index = {a};
      if (ev.unobserved(a)) { // refitted only beside a measured neighbour's capacity error
        c.start = {1.0};
        c.unobserved = true;
        c.evidence = fmt::format("{} is not measured; its capacity shows at its measured "
                                 "neighbours",
                                 nd.name);
        out.push_back(std::move(c));
        continue;
      }
      const ScreenFit f = ev.regress(
          [&](std::size_t k_case, int node, std::size_t k) {
            if (node != a) return 0.0;
            return -ev.cases[k_case].spec.nodes[static_cast<std::size_t>(a)].C *
                   ev.cases[k_case].dTdt[k][static_cast<std::size_t>(a)];
          },
          {a});
      c.start = {std::clamp(1.0 + f.coefficient, 0.2, 5.0)};
      c.screen = f.reduction;
      c.evidence = fmt::format("the unexplained heat flow of {} follows C dT/dt (correlation "
                               "{:.2f}): its capacity looks {} by a factor of about {:.3g}",
                               nd.name, f.correlation,
                               f.coefficient > 0 ? "too small" : "too large", 1.0 + f.coefficient);
      out.push_back(std::move(c));
    }
    return out;
  }

  void extend(const Candidate& c, const std::vector<double>& p,
              lang::NetworkSpec& spec) const override {
    spec.nodes[static_cast<std::size_t>(c.index[0])].C *= p[0];
  }

  // A node cannot be declared twice: the corrected capacity is a `NODE.C` override in every case
  // block (each case's own capacity times the factor); without case blocks it is a comment.
  std::string statement(const Candidate& c, const std::vector<double>& p,
                        const Evidence& ev) const override {
    if (!ev.declared_cases.empty())
      return fmt::format("# capacity_error: the capacity of {} is {} times the modelled one (set "
                         "in every case block)",
                         c.nodes[0], netlist_number(p[0]));
    return fmt::format("# capacity_error: declare {} with C = {} [J/K] ({} times the modelled one)",
                       c.nodes[0], netlist_number(capacity(ev.declared, c) * p[0]),
                       netlist_number(p[0]));
  }

  CaseLines case_statements(const Candidate& c, const std::vector<double>& p,
                            const Evidence& ev) const override {
    CaseLines out;
    for (const auto& d : ev.declared_cases)
      out[d.case_name] =
          fmt::format("{}.C = {} [J/K]", c.nodes[0], netlist_number(capacity(d, c) * p[0]));
    return out;
  }

private:
  static double capacity(const DeclaredSpec& d, const Candidate& c) {
    return d.spec.nodes.at(static_cast<std::size_t>(d.spec.node_index(c.nodes[0]))).C;
  }
};

HypothesisPlugin make_capacity_error() {
  return {.name = "capacity_error",
          .doc = "a node's heat capacity is wrong by a factor",
          .create = [] { return std::make_unique<CapacityError>(); },
          .screen = "-C dT/dt",
          .fitted = "factor (true C / model C)",
          .writes = "a.C = ... [J/K] in each case block (that case's C times the factor); without "
                    "case blocks a comment giving the corrected C"};
}

} // namespace
THERMNET_REGISTER(HypothesisPlugin, make_capacity_error);
} // namespace thermnet
