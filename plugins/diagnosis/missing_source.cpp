// Hypothesis 'missing_source': a node gains (or loses) a constant heat flow the model does not
// know of. Screen: each measured node's unexplained heat flow regressed on a constant.
#include "kernel/diagnosis/hypothesis.hpp"

#include <fmt/format.h>

namespace thermnet {
namespace {

class MissingSource final : public Hypothesis {
public:
  std::vector<Candidate> propose(const Evidence& ev) const override {
    std::vector<Candidate> out;
    if (ev.cases.empty()) return out;
    const auto& nodes = ev.cases.front().spec.nodes;
    for (int a = 0; a < static_cast<int>(nodes.size()); ++a) {
      Candidate c;
      c.kind = "missing_source";
      c.nodes = {nodes[static_cast<std::size_t>(a)].name};
      c.names = {"P"};
      c.lo = {-1e5};
      c.hi = {1e5};
      c.index = {a};
      if (ev.unobserved(a)) { // refitted only beside a measured neighbour's source
        c.unobserved = true;
        c.start = {0.0};
        c.evidence = fmt::format("{} is not measured; a steady heat there shows at its measured "
                                 "neighbours",
                                 c.nodes[0]);
        out.push_back(std::move(c));
        continue;
      }
      if (!ev.measured(a)) continue;
      const ScreenFit f = ev.regress(
          [&](std::size_t, int node, std::size_t) { return node == a ? 1.0 : 0.0; }, {a});
      c.start = {f.coefficient};
      c.screen = f.reduction;
      c.evidence = fmt::format("{} has a steady unexplained heat {} of about {:.3g} W", c.nodes[0],
                               f.coefficient >= 0 ? "gain" : "loss", std::abs(f.coefficient));
      out.push_back(std::move(c));
    }
    return out;
  }

  void extend(const Candidate& c, const std::vector<double>& p,
              lang::NetworkSpec& spec) const override {
    spec.elements.push_back(make_element("heater", unique_name(spec, "diag_source_" + c.nodes[0]),
                                         {c.index[0]}, {{"P", p[0]}}));
  }

  std::string statement(const Candidate& c, const std::vector<double>& p,
                        const Evidence& ev) const override {
    return fmt::format("heater {} {} P = {} [W]",
                       unique_name(ev.cases.front().spec, "diag_source_" + c.nodes[0]), c.nodes[0],
                       netlist_number(p[0]));
  }
};

HypothesisPlugin make_missing_source() {
  return {.name = "missing_source",
          .doc = "a constant heat gain or loss at a node",
          .create = [] { return std::make_unique<MissingSource>(); },
          .screen = "a constant",
          .fitted = "P [W] (negative: a sink)",
          .writes = "heater diag_source_a a P = ... [W]"};
}

} // namespace
THERMNET_REGISTER(HypothesisPlugin, make_missing_source);
} // namespace thermnet
