// Element plugin 'radiation': grey-body exchange Q = sigma GR (T_a^4 - T_b^4), in kelvin.
#include "kernel/core/element_registry.hpp"

namespace thermnet {
namespace {

constexpr double stefan_boltzmann = 5.670374419e-8;

/// Radiative exchange between two surfaces with a fixed radiative exchange factor GR.
class RadiationLink final : public NonlinearLink {
public:
  RadiationLink(int a, int b, double GR) : NonlinearLink(a, b), k_(stefan_boltzmann * GR) {}

protected:
  double evaluate(double ta, double tb, double& dq_da, double& dq_db) const override {
    const double ta3 = ta * ta * ta, tb3 = tb * tb * tb;
    dq_da = 4.0 * k_ * ta3;
    dq_db = -4.0 * k_ * tb3;
    return k_ * (ta3 * ta - tb3 * tb);
  }

private:
  double k_;
};

/// GR from the keys: given directly, or F A / (1/eps1 + 1/eps2 - 1).
double exchange_factor(const lang::KeyValues& v) {
  if (auto gr = v.find("GR"); gr != v.end()) return gr->second;
  return v.at("F") * v.at("A") / (1.0 / v.at("eps1") + 1.0 / v.at("eps2") - 1.0);
}

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
