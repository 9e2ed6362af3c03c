// Element plugin 'annulus_convection': natural convection in the air gap between two horizontal
// concentric cylinders (Raithby & Hollands; Incropera et al., eq. 9.58-9.60), with the
// conduction limit as a smooth floor. Q flows from terminal a to terminal b; either may be the
// inner cylinder (the correlation is symmetric in the sign of the temperature difference).
#include "kernel/core/element_registry.hpp"
#include "plugins/element/air_properties.hpp"

#include <cmath>
#include <numbers>

namespace thermnet {
namespace {

constexpr double gravity = 9.80665;
/// Exponent of the blend k_eff/k = (1 + X^n)^(1/n) between conduction (1) and convection (X).
constexpr double blend_n = 8.0;
/// Exponent of Ra in the correlation: X grows as Ra^(1/4).
constexpr double ra_exponent = 0.25;
static_assert(blend_n == 8.0 && blend_n * ra_exponent == 2.0,
              "evaluate() squares X^4 and takes the 8th root by three square roots");

/// Q = S k(Tm) R(Tm, dT) dT with R = (1 + X^n)^(1/n), X = c(Tm) |dT|^(1/4) and
/// c = 0.386 (Pr/(0.861+Pr))^(1/4) (F g delta^3 / (Tm nu alpha))^(1/4), where F is the geometric
/// factor of Rac = F Ra_delta.
class AnnulusConvection final : public NonlinearLink {
public:
  AnnulusConvection(int a, int b, double D_in, double D_out, double L, double scale)
      : NonlinearLink(a, b) {
    const double log_ratio = std::log(D_out / D_in);
    const double delta = 0.5 * (D_out - D_in);
    const double f_geo =
        std::pow(log_ratio, 4.0) /
        (std::pow(delta, 3.0) * std::pow(std::pow(D_in, -0.6) + std::pow(D_out, -0.6), 5.0));
    const double K0 = 0.386 * std::pow(f_geo * gravity * delta * delta * delta, ra_exponent);
    K0_n_ = std::pow(K0, blend_n);
    S_ = scale * 2.0 * std::numbers::pi * L / log_ratio;
    L_ = L;
    scale_ = scale;
  }

  /// Q is proportional to L and scale; the diameters are differenced by the kernel.
  bool key_derivative(double t, const double* T, const lang::KeySignals& rates,
                      double* dF) const override {
    double d_ln = 0.0;
    for (const auto& [key, rate] : rates) {
      if (key == "L")
        d_ln += rate.at(t) / L_;
      else if (key == "scale")
        d_ln += rate.at(t) / scale_;
      else
        return false;
    }
    add_proportional_rate(T, d_ln, dF);
    return true;
  }

private:
  /// Heat flow a -> b in W, with its partial derivatives in W/K.
  double evaluate(double ta, double tb, double& dq_da, double& dq_db) const override {
    const double tm = 0.5 * (ta + tb), dt = ta - tb;
    const air::Properties p = air::properties(tm);
    const double pr_b = p.Pr / (0.861 + p.Pr);
    const double dln_c = p.dPr * 0.25 * (1.0 / p.Pr - 1.0 / (0.861 + p.Pr)) -
                         ra_exponent * (1.0 / tm + p.dnu / p.nu + p.dalpha / p.alpha);
    // Y = X^n = K0^n (pr_b |dT| / (Tm nu alpha))^(n/4) with n/4 = 2: no transcendental function.
    const double base = pr_b * dt / (tm * p.nu * p.alpha);
    const double Y = K0_n_ * base * base;
    const double R = std::sqrt(std::sqrt(std::sqrt(1.0 + Y))); // (1 + Y)^(1/8)
    const double w = Y / (1.0 + Y);                            // d ln R / d ln Y times n
    const double dq_ddt = S_ * p.k * R * (1.0 + ra_exponent * w);
    const double dq_dtm = S_ * dt * R * (p.dk + p.k * w * dln_c);
    dq_da = 0.5 * dq_dtm + dq_ddt;
    dq_db = 0.5 * dq_dtm - dq_ddt;
    return S_ * p.k * R * dt;
  }

  double K0_n_ = 0.0; // (constant part of c)^n
  double S_ = 0.0;    // scale * 2 pi L / ln(Do/Di), m
  double L_ = 1.0;    // length, m
  double scale_ = 1.0;
};

ElementPlugin make_annulus_convection() {
  lang::ElementSchema s;
  s.kind = "annulus_convection";
  s.terminals = 2;
  s.doc = "natural convection in air between horizontal concentric cylinders (Raithby-Hollands)";
  s.keys.push_back(Key("D_in", lang::dim::length, "outer diameter of the inner cylinder [m]")
                       .required()
                       .positive());
  s.keys.push_back(Key("D_out", lang::dim::length, "inner diameter of the outer cylinder [m]")
                       .required()
                       .positive());
  s.keys.push_back(Key("L", lang::dim::length, "cylinder length [m]").required().positive());
  s.keys.push_back(Key("scale", lang::dim::none, "calibration multiplier of Q (default 1)")
                       .positive()
                       .otherwise(1.0));
  s.check = [](const lang::KeyValues& v) {
    std::vector<lang::KeyProblem> problems;
    auto din = v.find("D_in"), dout = v.find("D_out");
    if (din != v.end() && dout != v.end() && !(dout->second > din->second))
      problems.push_back({"D_out", "D_out must be larger than D_in"});
    return problems;
  };
  return ElementPlugin{std::move(s), [](const lang::ElementSpec& e) -> std::unique_ptr<Element> {
                         const lang::KeyValues v = e.key_values();
                         return std::make_unique<AnnulusConvection>(e.nodes()[0], e.nodes()[1],
                                                                    v.at("D_in"), v.at("D_out"),
                                                                    v.at("L"), v.at("scale"));
                       }};
}

} // namespace
THERMNET_REGISTER(ElementPlugin, make_annulus_convection);
} // namespace thermnet
