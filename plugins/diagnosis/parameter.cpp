// Hypothesis 'parameter': recalibrating the model's ranged params within their ranges explains the
// data. One candidate holding every ranged param, refitted by simulation.
#include "kernel/diagnosis/hypothesis.hpp"

#include <fmt/format.h>

namespace thermnet {
namespace {

class Parameter final : public Hypothesis {
public:
  bool recalibrates() const override { return true; }

  std::vector<Candidate> propose(const Evidence& ev) const override {
    Candidate c;
    c.kind = "parameter";
    for (const auto& p : ev.model->params()) {
      if (!p.ranged()) continue;
      c.names.push_back(p.name);
      c.start.push_back(p.value);
      c.lo.push_back(*p.lo);
      c.hi.push_back(*p.hi);
    }
    if (c.names.empty()) return {};
    c.evidence = "recalibrating the ranged params within their ranges";
    return {c};
  }

  lang::ParamValues overrides(const Candidate& c, const std::vector<double>& p) const override {
    lang::ParamValues v;
    for (std::size_t j = 0; j < c.names.size(); ++j)
      v.emplace(c.names[j], p[j]);
    return v;
  }

  std::string statement(const Candidate& c, const std::vector<double>& p,
                        const Evidence&) const override {
    std::string s;
    for (std::size_t j = 0; j < c.names.size(); ++j)
      s += fmt::format("{}# param {}: {} (SI; rewrite the declared value)", j ? "\n" : "",
                       c.names[j], netlist_number(p[j]));
    return s;
  }

  lang::ParamValues rewrites(const Candidate& c, const std::vector<double>& p) const override {
    return overrides(c, p);
  }
};

HypothesisPlugin make_parameter() {
  return {.name = "parameter",
          .doc = "recalibrating existing ranged params within their ranges",
          .create = [] { return std::make_unique<Parameter>(); },
          .screen = "none (always refitted when ranged params exist)",
          .fitted = "params {name: value}",
          .writes = "the declared values of the params, rewritten"};
}

} // namespace
THERMNET_REGISTER(HypothesisPlugin, make_parameter);
} // namespace thermnet
