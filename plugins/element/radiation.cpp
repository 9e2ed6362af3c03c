// Element plugin 'radiation': grey-body exchange Q = sigma GR (T_a^4 - T_b^4), in kelvin.
#include "kernel/core/element_registry.hpp"

namespace thermnet {
namespace {

constexpr double stefan_boltzmann = 5.670374419e-8;

/// The keys that set GR and d ln GR / d key of each (the partial derivatives of
/// GR = F A / (1/eps1 + 1/eps2 - 1), or of GR itself).
struct ExchangeFactor {
  double GR = 0.0;
  lang::KeyValues d_ln; // d ln GR / d key
};

/// GR from the keys: given directly, or F A / (1/eps1 + 1/eps2 - 1).
ExchangeFactor exchange_factor(const lang::KeyValues& v) {
  ExchangeFactor x;
  if (auto gr = v.find("GR"); gr != v.end()) {
    x.GR = gr->second;
    x.d_ln.emplace("GR", 1.0 / gr->second);
    return x;
  }
  const double F = v.at("F"), A = v.at("A"), e1 = v.at("eps1"), e2 = v.at("eps2");
  const double D = 1.0 / e1 + 1.0 / e2 - 1.0;
  x.GR = F * A / D;
  x.d_ln = {
      {"F", 1.0 / F}, {"A", 1.0 / A}, {"eps1", 1.0 / (e1 * e1 * D)}, {"eps2", 1.0 / (e2 * e2 * D)}};
  return x;
}

/// Radiative exchange between two surfaces with a fixed radiative exchange factor GR.
class RadiationLink final : public NonlinearLink {
public:
  RadiationLink(int a, int b, ExchangeFactor x)
      : NonlinearLink(a, b), k_(stefan_boltzmann * x.GR), d_ln_(std::move(x.d_ln)) {}

  /// Q is proportional to GR: dQ = Q d ln GR, with d ln GR the rates times the partials.
  bool key_derivative(double t, const double* T, const lang::KeySignals& rates,
                      double* dF) const override {
    double d_ln = 0.0;
    for (const auto& [key, rate] : rates) {
      const auto partial = d_ln_.find(key);
      if (partial == d_ln_.end()) return false;
      d_ln += partial->second * rate.at(t);
    }
    add_proportional_rate(T, d_ln, dF);
    return true;
  }

protected:
  double evaluate(double ta, double tb, double& dq_da, double& dq_db) const override {
    const double ta3 = ta * ta * ta, tb3 = tb * tb * tb;
    dq_da = 4.0 * k_ * ta3;
    dq_db = -4.0 * k_ * tb3;
    return k_ * (ta3 * ta - tb3 * tb);
  }

private:
  double k_;
  lang::KeyValues d_ln_; // d ln GR / d key of the keys that set GR
};

ElementPlugin make_radiation() {
  lang::ElementSchema s;
  s.kind = "radiation";
  s.terminals = 2;
  s.doc = "radiation exchange, Q = sigma GR (T_a^4 - T_b^4) in kelvin";
  s.keys.push_back(Key("GR", lang::dim::area, "radiative exchange factor [m^2]").positive());
  s.keys.push_back(Key("A", lang::dim::area, "radiating area [m^2]").positive());
  s.keys.push_back(Key("F", lang::dim::none, "view factor (default 1), with A, eps1 and eps2")
                       .fraction()
                       .otherwise(1.0)
                       .goes_with("A"));
  s.keys.push_back(Key("eps1", lang::dim::none, "emissivity of surface A, in (0, 1]").fraction());
  s.keys.push_back(Key("eps2", lang::dim::none, "emissivity of surface B, in (0, 1]").fraction());
  s.alternatives = {{"GR"}, {"A", "eps1", "eps2"}};
  return ElementPlugin{std::move(s), [](const lang::ElementSpec& e) -> std::unique_ptr<Element> {
                         return std::make_unique<RadiationLink>(e.nodes()[0], e.nodes()[1],
                                                                exchange_factor(e.key_values()));
                       }};
}

} // namespace
THERMNET_REGISTER(ElementPlugin, make_radiation);
} // namespace thermnet
