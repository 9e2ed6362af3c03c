// Element plugin 'cavity_convection': natural convection across a vertical plane air cavity
// (Catton; MacGregor & Emery; Incropera et al., eq. 9.50, 9.52, 9.53), with the conduction limit
// Nu = 1 as a smooth floor. The two walls are vertical, so the flow is symmetric in the sign of
// Ta - Tb and Q(Ta, Tb) = -Q(Tb, Ta).
#include "kernel/core/element_registry.hpp"
#include "plugins/element/air_properties.hpp"

#include <cmath>
#include <numbers>

namespace thermnet {
namespace {

constexpr double gravity = 9.80665;
/// Exponent of the blend Nu = (1 + X^n)^(1/n) between conduction (1) and convection (X).
constexpr double blend_n = 8.0;
static_assert(blend_n == 8.0, "evaluate() takes the 8th root by three square roots");

/// A correlation Nu_c = K0 Pr^e_pr (Pr/(b+Pr))^e_b (g L^3 dT / (Tm nu alpha))^p, K0 holding the
/// geometry; chosen by the aspect ratio H/L.
struct CavityLaw {
  double K0 = 0.0;   ///< constant factor, including (g L^3)^p and the aspect-ratio term
  double e_pr = 0.0; ///< exponent of Pr
  double e_b = 0.0;  ///< exponent of Pr/(b+Pr)
  double b = 0.2;    ///< constant in Pr/(b+Pr)
  double p = 0.25;   ///< exponent of Ra
};

/// Catton (1 < H/L < 2 and below, eq. 9.53), Catton (2 <= H/L <= 10, eq. 9.52), MacGregor &
/// Emery (H/L > 10, eq. 9.50).
CavityLaw cavity_law(double gap, double H) {
  const double r = H / gap, gl3 = gravity * gap * gap * gap;
  if (r < 2.0) return {0.18 * std::pow(gl3, 0.29), 0.0, 0.29, 0.2, 0.29};
  if (r <= 10.0) return {0.22 * std::pow(gl3, 0.28) * std::pow(r, -0.25), 0.0, 0.28, 0.2, 0.28};
  return {0.42 * std::pow(gl3, 0.25) * std::pow(r, -0.3), 0.012, 0.0, 0.2, 0.25};
}

/// Q = S k(Tm) Nu(Tm, dT) dT with Nu = (1 + X^n)^(1/n), X = Nu_c of the chosen law, S = A/gap.
class CavityConvection final : public NonlinearLink {
public:
  CavityConvection(int a, int b, double scale, double S, CavityLaw law)
      : NonlinearLink(a, b), scale_(scale), S_(S), law_(law), ln_K0_(std::log(law.K0)) {}

  /// Q is proportional to scale; the geometry (which also sets the law) is differenced by the
  /// kernel.
  bool key_derivative(double t, const double* T, const lang::KeySignals& rates,
                      double* dF) const override {
    if (rates.size() != 1 || rates.begin()->first != "scale") return false;
    add_proportional_rate(T, rates.begin()->second.at(t) / scale_, dF);
    return true;
  }

private:
  /// Heat flow a -> b in W, with its partial derivatives in W/K.
  double evaluate(double ta, double tb, double& dq_da, double& dq_db) const override {
    const double tm = 0.5 * (ta + tb), dt = ta - tb;
    const air::Properties p = air::properties(tm);
    const CavityLaw& l = law_;
    const double dln_c = p.dPr * (l.e_pr / p.Pr + l.e_b * (1.0 / p.Pr - 1.0 / (l.b + p.Pr))) -
                         l.p * (1.0 / tm + p.dnu / p.nu + p.dalpha / p.alpha);
    // Y = X^n; zero at dT = 0 (pure conduction). Terms with a zero exponent are skipped.
    double Y = 0.0;
    if (dt != 0.0) {
      double ln_x = ln_K0_ + l.p * std::log(std::fabs(dt) / (tm * p.nu * p.alpha));
      if (l.e_pr != 0.0) ln_x += l.e_pr * std::log(p.Pr);
      if (l.e_b != 0.0) ln_x += l.e_b * std::log(p.Pr / (l.b + p.Pr));
      Y = std::exp(blend_n * ln_x);
    }
    const double Nu = std::sqrt(std::sqrt(std::sqrt(1.0 + Y))); // (1 + Y)^(1/n), n = 8
    const double w = Y / (1.0 + Y);                             // d ln Nu / d ln X
    const double dq_ddt = S_ * p.k * Nu * (1.0 + l.p * w);
    const double dq_dtm = S_ * dt * Nu * (p.dk + p.k * w * dln_c);
    dq_da = 0.5 * dq_dtm + dq_ddt;
    dq_db = 0.5 * dq_dtm - dq_ddt;
    return S_ * p.k * Nu * dt;
  }

  double scale_; // calibration multiplier
  double S_;     // scale * A / gap, m
  CavityLaw law_;
  double ln_K0_; // log(law_.K0)
};

ElementPlugin make_cavity_convection() {
  lang::ElementSchema s;
  s.kind = "cavity_convection";
  s.terminals = 2;
  s.doc = "natural convection across a vertical plane air cavity (Catton, MacGregor-Emery)";
  s.keys.push_back(Key("A", lang::dim::area, "wall area [m^2]").required().positive());
  s.keys.push_back(Key("gap", lang::dim::length, "cavity thickness L [m]").required().positive());
  s.keys.push_back(
      Key("H", lang::dim::length, "cavity height [m] (default: diameter of a disc of area A)")
          .positive());
  s.keys.push_back(Key("scale", lang::dim::none, "calibration multiplier of Q (default 1)")
                       .positive()
                       .otherwise(1.0));
  return ElementPlugin{
      std::move(s), [](const lang::ElementSpec& e) -> std::unique_ptr<Element> {
        const lang::KeyValues v = e.key_values();
        const double A = v.at("A"), gap = v.at("gap");
        auto h = v.find("H");
        const double H = h != v.end() ? h->second : std::sqrt(4.0 * A / std::numbers::pi);
        return std::make_unique<CavityConvection>(e.nodes()[0], e.nodes()[1], v.at("scale"),
                                                  v.at("scale") * A / gap, cavity_law(gap, H));
      }};
}

} // namespace
THERMNET_REGISTER(ElementPlugin, make_cavity_convection);
} // namespace thermnet
