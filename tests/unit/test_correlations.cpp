// Unit tests of the temperature-dependent convection plugins (annulus_convection,
// cavity_convection) and of the air property fit they use.

#include "kernel/core/element_registry.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"
#include "lang/diagnostics.hpp"
#include "lang/model.hpp"
#include "lang/source.hpp"
#include "plugins/element/air_properties.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <utility>

namespace {

using thermnet::Element;

/// A layout for one two-terminal element on nodes 0 and 1: slot = 2 row + col.
class PairLayout final : public thermnet::JacobianLayout {
public:
  int slot(int row, int col) override { return 2 * row + col; }
};

/// Builds an element of a registered kind on nodes 0 and 1 from SI key values.
std::unique_ptr<Element> make_element(const std::string& kind,
                                      const std::map<std::string, double>& keys) {
  const thermnet::ElementPlugin* plugin = thermnet::ElementRegistry::global().find(kind);
  REQUIRE(plugin != nullptr);
  thermnet::lang::ElementSpec spec;
  spec.schema = &plugin->schema;
  spec.set_nodes(std::array{0, 1});
  for (const auto& [k, v] : keys)
    spec.set(k, thermnet::lang::Signal::of(v));
  auto e = plugin->create(spec);
  PairLayout layout;
  e->declare(layout);
  return e;
}

/// Heat flow a -> b and its derivatives from the element's stamp.
struct Stamped {
  double q = 0.0, dq_da = 0.0, dq_db = 0.0;
};

Stamped stamp(const Element& e, double ta, double tb) {
  const std::array<double, 2> T = {ta, tb};
  std::array<double, 2> F = {0.0, 0.0};
  std::array<double, 4> J = {0.0, 0.0, 0.0, 0.0};
  e.stamp(0.0, T.data(), F.data(), J.data());
  // Row 0 holds -dq: slots 0 (d/dTa) and 1 (d/dTb).
  return {-F[0], -J[0], -J[1]};
}

const std::map<std::string, double> barrel_gap = {
    {"D_in", 0.070}, {"D_out", 0.114}, {"L", 0.150}, {"scale", 1.0}};
const std::map<std::string, double> frame_gap = {
    {"D_in", 0.114}, {"D_out", 0.163}, {"L", 0.150}, {"scale", 1.0}};
const std::map<std::string, double> window_cavity = {
    {"A", std::numbers::pi * 0.02 * 0.02}, {"gap", 0.036}, {"scale", 1.0}};

/// Pure-conduction conductance of an annulus at mean temperature tm, W/K.
double annulus_conduction(const std::map<std::string, double>& g, double tm) {
  return 2.0 * std::numbers::pi * thermnet::air::properties(tm).k * g.at("L") /
         std::log(g.at("D_out") / g.at("D_in"));
}

} // namespace

TEST_CASE("air properties reproduce Incropera Table A.4") {
  struct Row {
    double T, k, nu, alpha, Pr;
  };
  const Row rows[] = {{250, 22.3e-3, 11.44e-6, 15.9e-6, 0.720},
                      {300, 26.3e-3, 15.89e-6, 22.5e-6, 0.707},
                      {350, 30.0e-3, 20.92e-6, 29.9e-6, 0.700},
                      {400, 33.8e-3, 26.41e-6, 38.3e-6, 0.690},
                      {200, 18.1e-3, 7.59e-6, 10.3e-6, 0.737}};
  for (const Row& r : rows) {
    const auto p = thermnet::air::properties(r.T);
    CHECK(p.k == doctest::Approx(r.k).epsilon(0.01));
    CHECK(p.nu == doctest::Approx(r.nu).epsilon(0.01));
    CHECK(p.alpha == doctest::Approx(r.alpha).epsilon(0.01));
    CHECK(p.Pr == doctest::Approx(r.Pr).epsilon(0.01));
  }
  // Derivatives match central differences inside the range; clamped (zero slope) outside.
  for (double T = 205.0; T < 400.0; T += 10.0) {
    const double h = 1e-3;
    const auto p = thermnet::air::properties(T), up = thermnet::air::properties(T + h),
               dn = thermnet::air::properties(T - h);
    CHECK(p.dk == doctest::Approx((up.k - dn.k) / (2 * h)).epsilon(1e-6));
    CHECK(p.dnu == doctest::Approx((up.nu - dn.nu) / (2 * h)).epsilon(1e-6));
    CHECK(p.dalpha == doctest::Approx((up.alpha - dn.alpha) / (2 * h)).epsilon(1e-6));
    CHECK(p.dPr == doctest::Approx((up.Pr - dn.Pr) / (2 * h)).epsilon(1e-5));
    CHECK(p.k > 0.0);
    CHECK(p.dk > 0.0);
  }
  CHECK(thermnet::air::properties(150.0).k == thermnet::air::properties(200.0).k);
  CHECK(thermnet::air::properties(150.0).dk == 0.0);
  CHECK(thermnet::air::properties(450.0).nu == thermnet::air::properties(400.0).nu);
}

TEST_CASE("annulus_convection conductance for the aerial camera geometry") {
  // The Raithby-Hollands correlation gives 0.07-0.11 W/K for the barrel gap (Di 70 mm, Do 114 mm,
  // L 150 mm) with air at 250-300 K and dT 2-20 K: k_eff/k is only 1.5-2.4 because Rac stays
  // below ~1e4. The study's 0.24-0.48 W/K is 2.5-5x higher: it cannot come from this correlation
  // alone (with the conduction floor at ~0.046 W/K, reaching 0.24 W/K needs Rac ~ 6e5); the study
  // presumably lumped other paths or a different convection model. We assert the band our physics
  // gives and keep `scale` for calibrating to measurements (the study's k5 range 0.1-0.5 W/K).
  auto barrel = make_element("annulus_convection", barrel_gap);
  auto frame = make_element("annulus_convection", frame_gap);
  for (double tm : {250.0, 275.0, 300.0}) {
    for (double dt : {2.0, 5.0, 10.0, 20.0}) {
      const double g1 = stamp(*barrel, tm + dt / 2, tm - dt / 2).q / dt;
      const double g2 = stamp(*frame, tm + dt / 2, tm - dt / 2).q / dt;
      MESSAGE("Tm = " << tm << " K, dT = " << dt << " K: barrel gap G = " << g1
                      << " W/K, frame gap G = " << g2 << " W/K");
      CHECK(g1 > 0.06);
      CHECK(g1 < 0.12);
      CHECK(g2 > 0.08);
      CHECK(g2 < 0.20);
      CHECK(g1 > annulus_conduction(barrel_gap, tm));
    }
  }
  // scale multiplies Q.
  auto scaled = barrel_gap;
  scaled["scale"] = 3.0;
  auto s = make_element("annulus_convection", scaled);
  CHECK(stamp(*s, 280.0, 270.0).q == doctest::Approx(3.0 * stamp(*barrel, 280.0, 270.0).q));
  // D_out must exceed D_in.
  const auto* plugin = thermnet::ElementRegistry::global().find("annulus_convection");
  CHECK(plugin->schema.check({{"D_in", 0.1}, {"D_out", 0.05}, {"L", 0.1}}).size() == 1);
  CHECK(plugin->schema.check({{"D_in", 0.1}, {"D_out", 0.1}, {"L", 0.1}}).size() == 1);
  CHECK(plugin->schema.check({{"D_in", 0.07}, {"D_out", 0.114}, {"L", 0.15}, {"scale", 1.0}})
            .empty());
}

TEST_CASE("cavity_convection coefficient for the window cavity") {
  // Window disc 40 mm (H defaults to that diameter), gap 36 mm: H/L = 1.1, Catton eq. 9.53.
  // With air at 250-300 K and dT 2-20 K the correlation gives h = 1.8-3.6 W/(m^2 K) (Nu 2.7-5.1),
  // below the study's 7.77-10.56 W/(m^2 K): at this Ra (1e4-2e5) no standard enclosure correlation
  // reaches Nu ~ 12-16. We assert the band our physics gives; `scale` calibrates (k7: 2-15).
  const double A = window_cavity.at("A"), gap = window_cavity.at("gap");
  auto cav = make_element("cavity_convection", window_cavity);
  for (double tm : {250.0, 275.0, 300.0}) {
    for (double dt : {2.0, 5.0, 10.0, 20.0}) {
      const double h = stamp(*cav, tm + dt / 2, tm - dt / 2).q / (dt * A);
      const double nu = h * gap / thermnet::air::properties(tm).k;
      MESSAGE("Tm = " << tm << " K, dT = " << dt << " K: h = " << h << " W/(m^2 K), Nu = " << nu);
      CHECK(h > 1.5);
      CHECK(h < 4.0);
      CHECK(nu > 1.0);
    }
  }
}

TEST_CASE("conduction floor: tiny dT gives k_eff = k and Nu = 1") {
  auto ann = make_element("annulus_convection", barrel_gap);
  auto cav = make_element("cavity_convection", window_cavity);
  const double tm = 280.0, dt = 1e-3;
  const double g_ann = stamp(*ann, tm + dt / 2, tm - dt / 2).q / dt;
  CHECK(g_ann == doctest::Approx(annulus_conduction(barrel_gap, tm)).epsilon(1e-6));
  const double g_cav = stamp(*cav, tm + dt / 2, tm - dt / 2).q / dt;
  const double k = thermnet::air::properties(tm).k;
  CHECK(g_cav ==
        doctest::Approx(k * window_cavity.at("A") / window_cavity.at("gap")).epsilon(1e-6));
  // dT = 0 exactly: no flow, conductance slope equals the conduction value.
  const Stamped z = stamp(*ann, tm, tm);
  CHECK(z.q == 0.0);
  CHECK(z.dq_da == doctest::Approx(annulus_conduction(barrel_gap, tm)).epsilon(1e-12));
  CHECK(z.dq_db == doctest::Approx(-annulus_conduction(barrel_gap, tm)).epsilon(1e-12));
}

TEST_CASE("Q and the Jacobian are continuous across the floor transition and dT = 0") {
  for (const std::string kind : {"annulus_convection", "cavity_convection"}) {
    auto e = make_element(kind, kind == "annulus_convection" ? barrel_gap : window_cavity);
    const double tm = 270.0;
    // dT from -5 K to 5 K in 1 mK steps crosses the conduction/convection transition (~0.5 K for
    // the annulus, ~0.02 K for the cavity) and dT = 0.
    Stamped prev = stamp(*e, tm - 2.5, tm + 2.5);
    double max_jump_q = 0.0, max_jump_j = 0.0;
    for (int i = -4999; i <= 5000; ++i) {
      const double dt = 1e-3 * i;
      const Stamped s = stamp(*e, tm + dt / 2, tm - dt / 2);
      max_jump_q = std::max(max_jump_q, std::fabs(s.q - prev.q) / std::fabs(s.dq_da));
      max_jump_j = std::max(max_jump_j, std::fabs(s.dq_da - prev.dq_da) / std::fabs(s.dq_da));
      max_jump_j = std::max(max_jump_j, std::fabs(s.dq_db - prev.dq_db) / std::fabs(s.dq_db));
      prev = s;
    }
    MESSAGE(kind << ": largest step of Q over 1 mK = " << max_jump_q
                 << " K x dQ/dTa; of the Jacobian, relative = " << max_jump_j);
    CHECK(max_jump_q < 2e-3); // Q moves by about dQ/dT x 1 mK
    CHECK(max_jump_j < 2e-2); // no jump in the Jacobian
  }
}

TEST_CASE("analytic Jacobian matches central differences; Q is antisymmetric") {
  auto ann = make_element("annulus_convection", barrel_gap);
  auto cav_short = make_element("cavity_convection", window_cavity);
  auto tall = window_cavity;
  tall["H"] = 0.2; // H/L = 5.6: Catton eq. 9.52
  auto cav_tall = make_element("cavity_convection", tall);
  auto slim = window_cavity;
  slim["gap"] = 0.01;
  slim["H"] = 0.2; // H/L = 20: MacGregor & Emery eq. 9.50
  auto cav_slim = make_element("cavity_convection", slim);
  const Element* elements[] = {ann.get(), cav_short.get(), cav_tall.get(), cav_slim.get()};
  const double h = 1e-4;
  int points = 0;
  for (const Element* e : elements) {
    for (double ta = 215.0; ta <= 385.0; ta += 17.0) {
      for (double tb : {ta - 30.0, ta - 7.0, ta - 0.8, ta - 0.05, ta, ta + 0.05, ta + 0.8, ta + 7.0,
                        ta + 30.0}) {
        if (0.5 * (ta + tb) < 201.0 || 0.5 * (ta + tb) > 399.0) continue;
        const Stamped s = stamp(*e, ta, tb);
        const double fd_a = (stamp(*e, ta + h, tb).q - stamp(*e, ta - h, tb).q) / (2 * h);
        const double fd_b = (stamp(*e, ta, tb + h).q - stamp(*e, ta, tb - h).q) / (2 * h);
        const double norm = std::max(std::fabs(s.dq_da), std::fabs(s.dq_db));
        CHECK(std::fabs(s.dq_da - fd_a) < 1e-6 * norm);
        CHECK(std::fabs(s.dq_db - fd_b) < 1e-6 * norm);
        // Antisymmetry, and flow() agrees with the stamp.
        CHECK(stamp(*e, tb, ta).q == doctest::Approx(-s.q).epsilon(1e-12));
        const std::array<double, 2> T = {ta, tb};
        CHECK(e->flow(0.0, T.data()) == doctest::Approx(s.q).epsilon(1e-12));
        ++points;
      }
    }
  }
  CHECK(points > 300);
}

TEST_CASE("a model with both kinds simulates to the steady state") {
  const auto path = std::filesystem::temp_directory_path() / "thermnet_test_correlations.tnet";
  {
    std::ofstream f(path);
    f << "model correlations\n"
         "boundary ambient T = -20\n"
         "node barrel C = 200 T0 = 0\n"
         "node frame C = 300 T0 = 0\n"
         "node lens C = 50 T0 = 0\n"
         "node window C = 50 T0 = 0\n"
         "heater film barrel P = 5\n"
         "annulus_convection gap1 barrel frame D_in = 70 [mm] D_out = 114 [mm] L = 150 [mm]\n"
         "convection skin frame ambient h = 5 A = 0.1\n"
         "conduction mount barrel lens k = 1 L = 10 [mm] A = 1e-4\n"
         "cavity_convection cav lens window A = pi * (20 [mm])^2 gap = 36 [mm]\n"
         "convection wskin window ambient h = 5 A = 0.00126\n"
         "case run { duration = 3e5 ; output = 1e4 }\n";
  }
  thermnet::lang::SourceManager sources;
  thermnet::lang::DiagnosticEngine diags(sources);
  auto model =
      thermnet::lang::Model::load(path.string(), thermnet::element_catalog(), sources, diags);
  REQUIRE(model != nullptr);
  model->lint(diags);
  CHECK(diags.error_count() == 0);
  thermnet::Network transient_net(model->instantiate("run"));
  const auto transient = thermnet::simulate(transient_net);
  thermnet::Network steady_net(model->instantiate("run"));
  thermnet::SimulationOptions opt;
  opt.steady = true;
  const auto steady = thermnet::simulate(steady_net, opt);
  REQUIRE(!transient.temps.empty());
  REQUIRE(steady.temps.size() == 1);
  const auto& end = transient.temps.back();
  for (std::size_t i = 0; i < end.size(); ++i) {
    MESSAGE(transient.names[i] << ": transient end " << end[i] - 273.15 << " degC, steady "
                               << steady.temps[0][i] - 273.15 << " degC");
    CHECK(end[i] == doctest::Approx(steady.temps[0][i]).epsilon(1e-4));
  }
  // The heater warms the barrel well above the frame: convection is active in the annulus.
  CHECK(steady.temps[0][1] - steady.temps[0][2] > 5.0);
  std::filesystem::remove(path);
}
