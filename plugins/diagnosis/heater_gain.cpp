// Hypothesis 'heater_gain': a heater delivers a different power than modelled (a factor). Screen:
// the unexplained heat flow of its node regressed on its power signal (coefficient factor - 1).
#include "kernel/hypothesis.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace thermnet {
namespace {

/// The signal as netlist text, in watts.
std::string signal_text(const lang::Signal& s) {
  if (s.is_constant()) return netlist_number(s.constant) + " [W]";
  std::string out = s.kind == lang::Signal::Kind::step ? "step(" : "pwl(";
  for (std::size_t i = 0; i < s.t.size(); ++i)
    out +=
        fmt::format("{}{}: {} [W]", i ? ", " : "", netlist_number(s.t[i]), netlist_number(s.v[i]));
  return out + ")";
}

class HeaterGain final : public Hypothesis {
public:
  std::vector<Candidate> propose(const Evidence& ev) const override {
    std::vector<Candidate> out;
    if (ev.cases.empty()) return out;
    const auto& spec = ev.cases.front().spec;
    for (int e = 0; e < static_cast<int>(spec.elements.size()); ++e) {
      const auto& el = spec.elements[static_cast<std::size_t>(e)];
      if (el.kind != "heater" || !el.has("P") || el.name.empty()) continue;
      const int node = el.nodes.at(0);
      if (!ev.measured(node)) continue;
      const ScreenFit f = ev.regress([&](std::size_t c, int row, std::size_t k) {
        if (row != node) return 0.0;
        const auto& ce = ev.cases[c];
        return ce.spec.elements[static_cast<std::size_t>(e)].values.at("P").at(ce.times()[k]);
      });
      Candidate c;
      c.kind = "heater_gain";
      c.element = el.name;
      c.nodes = {spec.nodes[static_cast<std::size_t>(node)].name};
      c.names = {"factor"};
      c.lo = {0.02};
      c.hi = {50.0};
      c.start = {std::clamp(1.0 + f.coefficient, 0.2, 5.0)};
      c.screen = f.reduction;
      c.index = {e, node};
      c.evidence = fmt::format("the unexplained heat flow of {} follows the power of {} "
                               "(correlation {:.2f}): it looks {:.3g} times the modelled power",
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

  std::string statement(const Candidate& c, const std::vector<double>& p,
                        const Evidence& ev) const override {
    // An extra heater on the same node carrying (factor - 1) P(t) gives the fitted power in every
    // case that keeps the declared P (a case that overrides P needs its own correction).
    const auto& spec = ev.cases.front().spec;
    const auto& P = spec.elements.at(static_cast<std::size_t>(c.index[0])).values.at("P");
    return fmt::format("heater {} {} P = {}", unique_name(spec, "diag_gain_" + c.element),
                       c.nodes[0], signal_text(P.scaled(p[0] - 1.0)));
  }
};

HypothesisPlugin make_heater_gain() {
  return {"heater_gain", "a heater delivers a different power than modelled (a factor)",
          [] { return std::make_unique<HeaterGain>(); }};
}

} // namespace
THERMNET_REGISTER_HYPOTHESIS(make_heater_gain);
} // namespace thermnet
