// Hypothesis 'heater_gain': a heater delivers a different power than modelled (a factor). Screen:
// the unexplained heat flow of its node regressed on its power signal (coefficient factor - 1).
#include "kernel/diagnosis/hypothesis.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace thermnet {
namespace {

class HeaterGain final : public Hypothesis {
public:
  std::vector<Candidate> propose(const Evidence& ev) const override {
    std::vector<Candidate> out;
    if (ev.cases.empty()) return out;
    const auto& spec = ev.cases.front().spec;
    for (int e : named_heaters(spec)) {
      const auto& el = spec.elements[static_cast<std::size_t>(e)];
      const int node = el.nodes()[0];
      const bool unobserved = ev.unobserved(node);
      const ScreenFit f =
          unobserved ? ScreenFit{}
                     : ev.regress(
                           [&](std::size_t c, int row, std::size_t k) {
                             if (row != node) return 0.0;
                             const auto& ce = ev.cases[c];
                             return ce.spec.elements[static_cast<std::size_t>(e)].values.at("P").at(
                                 ce.times()[k]);
                           },
                           {node});
      Candidate c;
      c.unobserved = unobserved;
      c.kind = "heater_gain";
      c.element = el.name;
      c.nodes = {spec.nodes[static_cast<std::size_t>(node)].name};
      c.names = {"factor"};
      c.lo = {0.02};
      c.hi = {50.0};
      c.start = {std::clamp(1.0 + f.coefficient, 0.2, 5.0)};
      c.screen = f.reduction;
      c.index = {e, node};
      c.evidence = unobserved
                       ? fmt::format("{} is not measured; the power of {} shows at its measured "
                                     "neighbours",
                                     c.nodes[0], el.name)
                       : fmt::format("the unexplained heat flow of {} follows the power of {} "
                                     "(correlation {:.2f}): it looks {:.3g} times the modelled "
                                     "power",
                                     c.nodes[0], el.name, f.correlation, 1.0 + f.coefficient);
      out.push_back(std::move(c));
    }
    return out;
  }

  void extend(const Candidate& c, const std::vector<double>& p,
              lang::NetworkSpec& spec) const override {
    auto& P = spec.elements.at(static_cast<std::size_t>(c.index[0])).values.at("P");
    P = P.scaled(p[0]);
  }

  // An extra heater on the same node carrying (factor - 1) P(t): it reads the heater's power by
  // name (`P = 0.12 * film.P`), so it follows whatever power a case gives the heater.
  std::string statement(const Candidate& c, const std::vector<double>& p,
                        const Evidence& ev) const override {
    return fmt::format("heater {} {} P = {} * {}.P", name_of(c, ev), c.nodes[0],
                       netlist_number(p[0] - 1.0), c.element);
  }

private:
  static std::string name_of(const Candidate& c, const Evidence& ev) {
    return unique_name(ev.declared.spec, "diag_gain_" + c.element);
  }
};

HypothesisPlugin make_heater_gain() {
  return {.name = "heater_gain",
          .doc = "a heater delivers a different power than modelled (a factor)",
          .create = [] { return std::make_unique<HeaterGain>(); },
          .screen = "the heater's P(t)",
          .fitted = "factor",
          .writes = "an extra heater diag_gain_h on the node with P = (factor - 1) * h.P, which "
                    "reads the heater's power in every case"};
}

} // namespace
THERMNET_REGISTER(HypothesisPlugin, make_heater_gain);
} // namespace thermnet
