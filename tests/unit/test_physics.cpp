// Physics verification: model text -> load -> instantiate -> simulate, against closed forms and
// analytic solutions (RC decay, radiative equilibrium, a 1-D slab, energy balance, thermostat
// switching, arithmetic nodes, composite and geometric conductances, signals, initial = steady).

#include "kernel/core/element_registry.hpp"
#include "kernel/core/integrator.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"
#include "lang/diagnostics.hpp"
#include "lang/model.hpp"

#include <doctest/doctest.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <unistd.h>
#include <vector>

#include "temp_dir.hpp"

using thermnet::test::TempDir;

namespace {

namespace fs = std::filesystem;
using thermnet::Network;
using thermnet::SimulationOptions;
using thermnet::SimulationResult;

constexpr double kZeroC = 273.15;
constexpr double kSigma = 5.670374419e-8;
constexpr double kPi = 3.14159265358979323846;

/// Loads model text (written as model.tnet in dir), requires no errors, instantiates a case.
thermnet::lang::NetworkSpec spec_from(const TempDir& dir, const std::string& text,
                                      const std::string& case_name = "") {
  fs::path f = dir.write("model.tnet", text);
  thermnet::lang::SourceManager sources;
  thermnet::lang::DiagnosticEngine diags(sources);
  auto model = thermnet::lang::Model::load(f.string(), thermnet::element_catalog(), sources, diags);
  REQUIRE(model != nullptr);
  model->lint(diags);
  INFO(thermnet::lang::render_text(diags));
  REQUIRE(diags.error_count() == 0);
  return model->instantiate(case_name);
}

thermnet::lang::NetworkSpec spec_from(const std::string& text, const std::string& case_name = "") {
  TempDir dir;
  return spec_from(dir, text, case_name);
}

int col(const SimulationResult& r, const std::string& name) {
  auto it = std::find(r.names.begin(), r.names.end(), name);
  REQUIRE(it != r.names.end());
  return static_cast<int>(it - r.names.begin());
}

SimulationOptions tight(double tol = 1e-10) {
  SimulationOptions o;
  o.solver.rtol = tol;
  o.solver.atol = tol;
  return o;
}

/// Steady temperature of node `node` (K) for a model.
double steady_T(const std::string& text, const std::string& node) {
  Network net(spec_from(text));
  SimulationOptions o = tight();
  o.steady = true;
  SimulationResult r = thermnet::simulate(net, o);
  REQUIRE(r.times.size() == 1);
  return r.temps[0][static_cast<std::size_t>(col(r, node))];
}

// ---------------------------------------------------------------------------------------------

/// Max |T - exact| over a one-node RC decay (C = 1000 J/K, G = 10 W/K to 0 degC, T0 = 100 degC:
/// T = 100 exp(-t/100) degC), sampled every 0.5 s over 600 s.
double rc_decay_error(const SimulationOptions& o) {
  const std::string text = R"(
boundary amb T = 0
node n C = 1000 [J/K] T0 = 100
conductance g n amb G = 10
case decay { duration = 600; output = 0.5 }
)";
  Network net(spec_from(text));
  SimulationResult r = thermnet::simulate(net, o);
  int c = col(r, "n");
  double err = 0;
  for (std::size_t k = 0; k < r.times.size(); ++k) {
    double exact = kZeroC + 100.0 * std::exp(-r.times[k] / 100.0);
    err = std::max(err, std::abs(r.temps[k][static_cast<std::size_t>(c)] - exact));
  }
  CHECK(r.times.size() == 1201);
  CHECK(r.times.back() == doctest::Approx(600.0).epsilon(1e-15));
  return err;
}

TEST_CASE("physics: one-node RC decay follows the exponential within the tolerance") {
  // The tolerances act on kelvin (|T| ~ 373 K), so the local error weight is rtol*373 + atol;
  // the global error of CVODE BDF stays within a small multiple of it and shrinks with it.
  const double err_default = rc_decay_error(SimulationOptions{});
  const double err_8 = rc_decay_error(tight(1e-8));
  const double err_10 = rc_decay_error(tight(1e-10));
  MESSAGE("RC decay max error: rtol=atol=1e-6 (default) " << err_default << " K, 1e-8 " << err_8
                                                          << " K, 1e-10 " << err_10 << " K");
  auto weight = [](double tol) { return tol * (kZeroC + 100) + tol; };
  CHECK(err_default < 10 * weight(1e-6)); // 3.7e-3 K
  CHECK(err_8 < 10 * weight(1e-8));
  CHECK(err_10 < 10 * weight(1e-10)); // 3.7e-7 K
  CHECK(err_8 < 1e-4);
  CHECK(err_10 < 1e-6);
  CHECK(err_default / err_10 > 1e3); // converges as the tolerance is tightened
}

TEST_CASE("physics: radiative equilibrium matches (Tb^4 + P/(sigma GR))^(1/4)") {
  const std::string text = R"(
boundary space T = 20
node plate C = 100 [J/K] T0 = 20
radiation rad plate space GR = 0.01
heater h plate P = 50
case hot { duration = 20000; output = 100 }
)";
  const double Tb = 20 + kZeroC;
  const double exact = std::pow(std::pow(Tb, 4) + 50.0 / (kSigma * 0.01), 0.25);
  double Ts = steady_T(text, "plate");
  Network net(spec_from(text));
  SimulationResult r = thermnet::simulate(net, tight(1e-10));
  double Tt = r.temps.back()[static_cast<std::size_t>(col(r, "plate"))];
  MESSAGE("radiation equilibrium exact " << exact << " K; steady error " << Ts - exact
                                         << " K; transient (20000 s) error " << Tt - exact << " K");
  CHECK(std::abs(Ts - exact) < 1e-8);
  CHECK(std::abs(Tt - exact) < 1e-6);
}

// Slab 0 < x < L, face x = 0 held at Ts from t = 0, face x = L adiabatic, initially Ti
// (Carslaw & Jaeger 3.3): (T - Ts)/(Ti - Ts) = sum 4/((2n+1) pi) sin((2n+1) pi x / (2L))
// exp(-(2n+1)^2 pi^2 alpha t / (4 L^2)).
double slab_exact(double x, double t, double L, double alpha, double Ti, double Ts) {
  double s = 0;
  for (int n = 0; n < 2000; ++n) {
    double m = 2 * n + 1;
    s += 4 / (m * kPi) * std::sin(m * kPi * x / (2 * L)) *
         std::exp(-m * m * kPi * kPi * alpha * t / (4 * L * L));
  }
  return Ts + (Ti - Ts) * s;
}

/// Cell-centred finite-volume slab of N cells; returns the error at x = L/2, t = 1000 s.
double slab_error(int N) {
  // L = 0.1 m, k = 1 W/(m K), rho c = 1e6 J/(m^3 K), A = 1 m^2: alpha = 1e-6, Fo = 0.1 at 1000 s.
  std::string m = "const L = 0.1\nconst N = " + std::to_string(N) +
                  "\nconst dx = L / N\nboundary face T = 100\n";
  for (int i = 0; i < N; ++i)
    m += "node c" + std::to_string(i) + " C = 1e6 * dx\n";
  m += "conduction k0 face c0 k = 1 L = dx / 2 A = 1\n";
  for (int i = 0; i + 1 < N; ++i)
    m += "conduction k" + std::to_string(i + 1) + " c" + std::to_string(i) + " c" +
         std::to_string(i + 1) + " k = 1 L = dx A = 1\n";
  m += "case step { duration = 1000; output = 1000; initial = 0 }\n";
  Network net(spec_from(m));
  SimulationResult r = thermnet::simulate(net, tight(1e-10));
  REQUIRE(r.times.back() == doctest::Approx(1000.0));
  const auto& row = r.temps.back();
  const double dx = 0.1 / N;
  // linear interpolation between the cell centres around x = L/2
  double xm = 0.05;
  int i = static_cast<int>(std::floor(xm / dx - 0.5));
  double xi = (i + 0.5) * dx;
  double w = (xm - xi) / dx;
  const auto cell = [&](int k) {
    return row[static_cast<std::size_t>(col(r, fmt::format("c{}", k)))];
  };
  double Ta = cell(i);
  double Tb = (w > 1e-12) ? cell(i + 1) : Ta;
  double Tnum = (1 - w) * Ta + w * Tb;
  double exact = slab_exact(xm, 1000.0, 0.1, 1e-6, kZeroC, kZeroC + 100);
  return std::abs(Tnum - exact);
}

TEST_CASE("physics: 1-D slab with a suddenly imposed face temperature converges (2nd order)") {
  std::vector<int> Ns{5, 10, 20, 40};
  std::vector<double> errs;
  for (int N : Ns)
    errs.push_back(slab_error(N));
  for (std::size_t i = 0; i < Ns.size(); ++i)
    MESSAGE("slab N = " << Ns[i] << ": |error| at x = L/2, Fo = 0.1: " << errs[i] << " K");
  for (std::size_t i = 0; i + 1 < Ns.size(); ++i) {
    double order = std::log2(errs[i] / errs[i + 1]);
    MESSAGE("observed order " << Ns[i] << " -> " << Ns[i + 1] << ": " << order);
    CHECK(errs[i + 1] < errs[i]);
    // N = 5 puts a cell centre at L/2 (no interpolation) and is pre-asymptotic: order checked
    // from N = 10 on
    if (i > 0) {
      CHECK(order > 1.8);
      CHECK(order < 2.2);
    }
  }
  CHECK(errs.back() < 0.01); // K, on a 100 K step
}

TEST_CASE("physics: energy balance with radiation, a step heater and a pwl boundary") {
  const std::string text = R"(
boundary amb T = pwl(0: 20, 1000: -10, 1800: 5)
node n1 C = 500 T0 = 30
node n2 C = 300 T0 = 10
node n3 C = 200
heater h n1 P = step(0: 20, 600: 0, 1200: 10)
conductance g12 n1 n2 G = 2
conductance g23 n2 n3 G = 1.5
radiation rad n2 amb GR = 0.02
convection cv n3 amb h = 5 A = 0.1
case run { duration = 2000; output = 0.05 }
)";
  Network net(spec_from(text));
  SimulationResult r = thermnet::simulate(net, tight(1e-10));
  const auto& unk = net.unknown_nodes();
  const auto& caps = net.capacities();
  auto unknowns = [&](std::size_t k) {
    std::vector<double> T;
    for (int i : unk)
      T.push_back(r.temps[k][static_cast<std::size_t>(i)]);
    return T;
  };
  double heat = 0, loss = 0;
  for (std::size_t k = 0; k + 1 < r.times.size(); ++k) {
    double t0 = r.times[k], t1 = r.times[k + 1];
    auto T0 = unknowns(k), T1 = unknowns(k + 1);
    // left limit at t1 so a step at t1 does not leak into [t0, t1]
    double t1m = std::nextafter(t1, -std::numeric_limits<double>::infinity());
    heat += 0.5 * (t1 - t0) * (net.source_power(t0, T0.data()) + net.source_power(t1m, T1.data()));
    loss += 0.5 * (t1 - t0) * (net.boundary_loss(t0, T0.data()) + net.boundary_loss(t1, T1.data()));
  }
  auto Tfirst = unknowns(0), Tlast = unknowns(r.times.size() - 1);
  double stored = 0;
  for (std::size_t i = 0; i < Tfirst.size(); ++i)
    stored += caps[i] * (Tlast[i] - Tfirst[i]);
  const double heat_exact = 20 * 600 + 10 * 800;
  double rel = std::abs(heat - stored - loss) / heat;
  MESSAGE("energy: heater " << heat << " J (exact " << heat_exact << "), stored " << stored
                            << " J, to boundaries " << loss << " J, relative imbalance " << rel);
  CHECK(std::abs(heat - heat_exact) < 1e-9 * heat_exact);
  CHECK(rel < 1e-6);
}

TEST_CASE("physics: thermostat switching times match the RC solution") {
  // C = 1000 J/K, G = 10 W/K to 0 degC, P = 500 W: T_inf = 50 degC, RC = 100 s; band 30..40.
  const std::string text = R"(
boundary amb T = 0
node n C = 1000 T0 = 20
conductance g n amb G = 10
thermostat ts n P = 500 on = 30 off = 40
case cycle { duration = 2000; output = 1 }
)";
  const double RC = 100, Tinf = 50;
  // expected switch times
  std::vector<double> expected;
  double t = RC * std::log((Tinf - 20) / (Tinf - 40)); // first switch off
  bool heating = false;                                // after the first switch
  const double t_off = RC * std::log(40.0 / 30.0);     // cooling 40 -> 30
  const double t_on = RC * std::log((Tinf - 30) / (Tinf - 40));
  while (t < 2000) {
    expected.push_back(t);
    t += heating ? t_on : t_off;
    heating = !heating;
  }
  Network net(spec_from(text));
  std::vector<double> T = net.initial_state();
  std::vector<double> times;
  for (int k = 0; k <= 20000; ++k)
    times.push_back(0.1 * k);
  std::vector<double> ts, Ts, Ps;
  auto cb = [&](double tt, const std::vector<double>& x) {
    ts.push_back(tt);
    Ts.push_back(x[0]);
    Ps.push_back(net.source_power(tt, x.data()));
  };
  thermnet::SolverOptions so;
  so.rtol = so.atol = 1e-10;
  auto stats = thermnet::integrate(net, T, 0.0, 2000.0, times, cb, so);
  // Switch times: where the heater state changes between samples; located from the sample just
  // before by the analytic time to reach the threshold from that sample's temperature.
  std::vector<double> found;
  double Tmax = -1e9, Tmin = 1e9;
  for (std::size_t k = 0; k + 1 < ts.size(); ++k) {
    if (ts[k] > 150) {
      Tmax = std::max(Tmax, Ts[k]);
      Tmin = std::min(Tmin, Ts[k]);
    }
    if (Ps[k] == Ps[k + 1]) continue;
    double Tk = Ts[k] - kZeroC;
    if (Ps[k] > 0) // heating towards 50, switching off at 40
      found.push_back(ts[k] + RC * std::log((Tinf - Tk) / (Tinf - 40)));
    else // cooling towards 0, switching on at 30
      found.push_back(ts[k] + RC * std::log(Tk / 30.0));
  }
  MESSAGE("thermostat: expected " << expected.size() << " switches, sampled " << found.size()
                                  << ", solver events " << stats.events);
  REQUIRE(found.size() == expected.size());
  CHECK(stats.events == static_cast<long>(expected.size()));
  double worst = 0;
  for (std::size_t i = 0; i < found.size(); ++i)
    worst = std::max(worst, std::abs(found[i] - expected[i]));
  MESSAGE("thermostat: worst switching time error "
          << worst << " s; band overshoot " << Tmax - (40 + kZeroC) << " / " << (30 + kZeroC) - Tmin
          << " K");
  CHECK(worst < 1e-3);
  CHECK(Tmax < 40 + kZeroC + 1e-4);
  CHECK(Tmin > 30 + kZeroC - 1e-4);

  SUBCASE("switch count over a long run") {
    Network net2(spec_from(text));
    SimulationOptions o;
    o.duration = 100000;
    o.output = 100;
    SimulationResult r = thermnet::simulate(net2, o);
    // 1 first switch + full periods (t_off + t_on) each giving 2 switches
    long n = 0;
    double tt = RC * std::log(3.0);
    bool h = false;
    while (tt < 100000) {
      ++n;
      tt += h ? t_on : t_off;
      h = !h;
    }
    MESSAGE("thermostat long run: expected " << n << " switches, solver events " << r.stats.events);
    CHECK(r.stats.events == n);
  }
}

TEST_CASE("physics: an arithmetic node equals the series conductance it stands for") {
  const std::string full = R"(
boundary amb T = pwl(0: 20, 500: 60)
node n C = 100 T0 = 80
node mid C = 0
conductance g1 n mid G = 3
conductance g2 mid amb G = 6
heater h n P = step(0: 0, 300: 40)
case c { duration = 1000; output = 1 }
)";
  const std::string reduced = R"(
boundary amb T = pwl(0: 20, 500: 60)
node n C = 100 T0 = 80
conductance g n amb G = 2
heater h n P = step(0: 0, 300: 40)
case c { duration = 1000; output = 1 }
)";
  Network a(spec_from(full)), b(spec_from(reduced));
  SimulationResult ra = thermnet::simulate(a, tight(1e-10));
  SimulationResult rb = thermnet::simulate(b, tight(1e-10));
  REQUIRE(ra.times.size() == rb.times.size());
  double err = 0, err_mid = 0;
  for (std::size_t k = 0; k < ra.times.size(); ++k) {
    double Tn = ra.temps[k][static_cast<std::size_t>(col(ra, "n"))];
    double Tamb = ra.temps[k][static_cast<std::size_t>(col(ra, "amb"))];
    err = std::max(err, std::abs(Tn - rb.temps[k][static_cast<std::size_t>(col(rb, "n"))]));
    double mid_exact = (3 * Tn + 6 * Tamb) / 9;
    err_mid = std::max(err_mid,
                       std::abs(ra.temps[k][static_cast<std::size_t>(col(ra, "mid"))] - mid_exact));
  }
  MESSAGE("arithmetic node: max |T_n - T_n(reduced)| " << err << " K, max |T_mid - (3Tn+6Tamb)/9| "
                                                       << err_mid << " K; integrator "
                                                       << ra.stats.integrator);
  CHECK(err < 1e-6);
  CHECK(err_mid < 1e-7); // IDA interpolates algebraic unknowns between steps
}

TEST_CASE("physics: a thermostat's power may be a signal, also in a case override") {
  // RC = 100 s to 0 degC, P = 20 W while on and before 100 s, 0 after (on 5, off 8): off at
  // t1 = 100 ln(20/12), on again at t2 = t1 + 100 ln(8/5), then T(100) = 20 - 15 exp(-(100 -
  // t2)/100) decays freely since the power is gone: T(200) = T(100) / e.
  const std::string text = R"(
boundary e T = 0
node a C = 100 T0 = 0
conductance g a e G = 1
thermostat t a P = step(0: 20, 100: 0) on = 5 off = 8
case c { duration = 200; output = 100 }
case half {
  duration = 200
  output = 100
  t.P = 6
}
)";
  Network net(spec_from(text, "c"));
  SimulationResult r = thermnet::simulate(net, tight(1e-10));
  const double t2 = 100.0 * std::log(20.0 / 12.0) + 100.0 * std::log(8.0 / 5.0);
  const double at100 = 20.0 - 15.0 * std::exp(-(100.0 - t2) / 100.0);
  const auto a = static_cast<std::size_t>(col(r, "a"));
  REQUIRE(r.times.size() == 3);
  CHECK(r.temps[1][a] - kZeroC == doctest::Approx(at100).epsilon(1e-6));
  CHECK(r.temps[2][a] - kZeroC == doctest::Approx(at100 * std::exp(-1.0)).epsilon(1e-6));
  CHECK(r.stats.events == 2);

  // P = 6 W: never reaches 'off' = 8 (T -> 6 (1 - exp(-t/100))), so it heats throughout.
  Network half(spec_from(text, "half"));
  SimulationResult rh = thermnet::simulate(half, tight(1e-10));
  CHECK(rh.temps[2][a] - kZeroC == doctest::Approx(6.0 * (1.0 - std::exp(-2.0))).epsilon(1e-6));
}

TEST_CASE("physics: --steady puts thermostats in a consistent state, or says they cycle") {
  // Heating, the node settles at P/G = 20 degC, inside the band 15..25: on is consistent.
  const std::string in_band = R"(
boundary e T = 0
node a C = 100 T0 = 10
conductance g a e G = 1
thermostat t a P = 20 on = 15 off = 25
)";
  CHECK(steady_T(in_band, "a") - kZeroC == doctest::Approx(20.0));
  // Heating it would settle at 40 > off = 22, off at 0 < on = 18: it cycles, no steady state.
  const std::string cycling = R"(
boundary e T = 0
node a C = 1000 T0 = 10
conductance g a e G = 0.5
thermostat t a P = 20 on = 18 off = 22
)";
  Network net(spec_from(cycling));
  SimulationOptions o = tight();
  o.steady = true;
  CHECK_THROWS_AS(thermnet::simulate(net, o), thermnet::SolverError);
}

TEST_CASE("physics: a thermostat starts from the temperature of an arithmetic node it senses") {
  // The arithmetic node s sits at (a + e)/2 = 0 degC at t = 0, below 'on' = 5 (its own T0
  // default of 20 degC must not decide): the heater is on from the start, and a approaches
  // the steady value P/(G + G/2) = 13.33 degC as 13.33 (1 - exp(-t G_eff / C)).
  const std::string sensed = R"(
boundary e T = 0
node a C = 100 T0 = 0
node s C = 0
conductance g a e G = 1
conductance g2 a s G = 1
conductance g3 s e G = 1
thermostat t a P = 20 on = 5 off = 8 sense = s
case c { duration = 200; output = 200 }
)";
  Network net(spec_from(sensed));
  SimulationResult r = thermnet::simulate(net, tight(1e-9));
  const double a = r.temps.back()[static_cast<std::size_t>(col(r, "a"))] - kZeroC;
  CHECK(a == doctest::Approx(40.0 / 3.0 * (1.0 - std::exp(-200.0 * 1.5 / 100.0))).epsilon(1e-6));

  // A thermostat heating an arithmetic node: off it would sit at 0 < 'on', so it is on, and
  // on it sits at P/G = 20 degC, inside the band: it stays on.
  const std::string heated = R"(
boundary e T = 0
node a C = 0
conductance g a e G = 1
thermostat t a P = 20 on = 18 off = 22
case c { duration = 100; output = 50 }
)";
  Network net2(spec_from(heated));
  SimulationResult r2 = thermnet::simulate(net2, tight(1e-9));
  for (const auto& row : r2.temps)
    CHECK(row[static_cast<std::size_t>(col(r2, "a"))] - kZeroC == doctest::Approx(20.0));

  // Heated it would sit at P/G = 30 degC, above 'off'; unheated at 0 degC, below 'on': no state
  // is consistent, and the run fails at t = 0 naming the thermostat (it used to run on at 30 degC
  // with the heater on all the time).
  std::string none = heated;
  none.replace(none.find("P = 20 on = 18 off = 22"), 23, "P = 30 on = 10 off = 20");
  Network net3(spec_from(none));
  try {
    (void)thermnet::simulate(net3, tight(1e-9));
    FAIL("no error for a thermostat without a consistent state");
  } catch (const thermnet::SolverError& e) {
    CHECK(std::string(e.what()).find("thermostat 't'") != std::string::npos);
    CHECK(e.time == 0.0);
  }
  // The same becomes inconsistent during the run: P = 15 W keeps it at 15 degC (on) while the
  // boundary is cold; once the boundary passes 5 degC the heated node would pass 'off' = 20 degC,
  // and unheated it would sit below 'on' = 10 degC. The run stops there, at t = 50 s.
  std::string ramp = none;
  ramp.replace(ramp.find("boundary e T = 0"), 16, "boundary e T = pwl(0: 0, 100: 10)");
  ramp.replace(ramp.find("P = 30"), 6, "P = 15");
  Network net4(spec_from(ramp));
  try {
    (void)thermnet::simulate(net4, tight(1e-9));
    FAIL("no error when the thermostat's state stops being consistent");
  } catch (const thermnet::SolverError& e) {
    CHECK(std::string(e.what()).find("thermostat 't'") != std::string::npos);
    CHECK(e.time == doctest::Approx(50.0).epsilon(1e-6));
  }
}

TEST_CASE("physics: composite and geometric conductances match hand computation") {
  // A node with a heater P = 10 W, connected to a 0 degC boundary only through the element under
  // test: G = P / (T - 0).
  auto measured_G = [](const std::string& element) {
    std::string text = "boundary amb T = 0\nnode n C = 100\nheater h n P = 10\n" + element +
                       "\ncase c { duration = 1 }\n";
    return 10.0 / (steady_T(text, "n") - kZeroC);
  };
  SUBCASE("series") {
    double G = measured_G("series s n amb { contact h = 2500 A = 30e-4 ; conduction k = 0.25 "
                          "L = 3 [mm] A = 54.8 [mm^2] ; resistor R = 0.5 }");
    double exact = 1 / (1 / (2500 * 30e-4) + 3e-3 / (0.25 * 54.8e-6) + 0.5);
    MESSAGE("series G " << G << " exact " << exact);
    CHECK(G == doctest::Approx(exact).epsilon(1e-9));
  }
  SUBCASE("parallel") {
    double G = measured_G(
        "parallel p n amb { conductance G = 2 ; resistor R = 0.5 ; convection h = 10 A = 0.3 }");
    double exact = 2 + 2 + 3;
    MESSAGE("parallel G " << G << " exact " << exact);
    CHECK(G == doctest::Approx(exact).epsilon(1e-9));
  }
  SUBCASE("cylinder_conduction") {
    double G = measured_G("cylinder_conduction cy n amb k = 15 r_in = 10 [mm] r_out = 20 [mm] "
                          "L = 0.5");
    double exact = 2 * kPi * 15 * 0.5 / std::log(2.0);
    MESSAGE("cylinder G " << G << " exact " << exact);
    CHECK(G == doctest::Approx(exact).epsilon(1e-9));
  }
  SUBCASE("radiation with A, F, eps1, eps2") {
    std::string text = "boundary amb T = 0\nnode n C = 100\nheater h n P = 10\n"
                       "radiation r n amb A = 0.2 F = 0.7 eps1 = 0.85 eps2 = 0.1\n"
                       "case c { duration = 1 }\n";
    double T = steady_T(text, "n");
    double GR = 0.7 * 0.2 / (1 / 0.85 + 1 / 0.1 - 1);
    double exact = std::pow(std::pow(kZeroC, 4) + 10 / (kSigma * GR), 0.25);
    double GR_measured = 10 / (kSigma * (std::pow(T, 4) - std::pow(kZeroC, 4)));
    MESSAGE("radiation GR " << GR_measured << " exact " << GR << "; T " << T << " exact " << exact);
    CHECK(GR_measured == doctest::Approx(GR).epsilon(1e-9));
    CHECK(T == doctest::Approx(exact).epsilon(1e-12));
  }
  SUBCASE("radiation F defaults to 1") {
    std::string text = "boundary amb T = 0\nnode n C = 100\nheater h n P = 10\n"
                       "radiation r n amb A = 0.2 eps1 = 0.5 eps2 = 0.5\n"
                       "case c { duration = 1 }\n";
    double T = steady_T(text, "n");
    double GR = 0.2 / (1 / 0.5 + 1 / 0.5 - 1);
    double GR_measured = 10 / (kSigma * (std::pow(T, 4) - std::pow(kZeroC, 4)));
    CHECK(GR_measured == doctest::Approx(GR).epsilon(1e-9));
  }
}

TEST_CASE("physics: step and pwl boundaries are exact at corners; the node stays continuous") {
  const std::string text = R"(
boundary bs T = step(0: 20, 100: 50, 250: 10)
boundary bp T = pwl(50: 20, 150: 80, 200: 80, 300: 0)
node ns C = 1000 T0 = 20
node np C = 1000 T0 = 20
conductance gs ns bs G = 10
conductance gp np bp G = 10
case c { duration = 400; output = 10 }
)";
  Network net(spec_from(text));
  auto spec = net.spec();
  int is = spec.node_index("bs"), ip = spec.node_index("bp");
  int ns = spec.node_index("ns"), np = spec.node_index("np");
  auto sig = [&](int i, double t) {
    return spec.nodes[static_cast<std::size_t>(i)].T.at(t) - kZeroC;
  };
  const double eps = 1e-9;
  // step: the new value holds from the corner on; the old one just before
  CHECK(sig(is, 0) == doctest::Approx(20).epsilon(1e-14));
  CHECK(sig(is, 100 - eps) == doctest::Approx(20).epsilon(1e-14));
  CHECK(sig(is, 100) == doctest::Approx(50).epsilon(1e-14));
  CHECK(sig(is, 250) == doctest::Approx(10).epsilon(1e-14));
  CHECK(sig(is, 1e6) == doctest::Approx(10).epsilon(1e-14));
  // pwl: exact at corners, constant outside, linear between
  CHECK(sig(ip, 0) == doctest::Approx(20).epsilon(1e-14));
  CHECK(sig(ip, 50) == doctest::Approx(20).epsilon(1e-14));
  CHECK(sig(ip, 100) == doctest::Approx(50).epsilon(1e-14));
  CHECK(sig(ip, 150) == doctest::Approx(80).epsilon(1e-14));
  CHECK(sig(ip, 200) == doctest::Approx(80).epsilon(1e-14));
  CHECK(sig(ip, 300) == doctest::Approx(0).scale(1));
  CHECK(sig(ip, 1e6) == doctest::Approx(0).scale(1));
  CHECK(std::abs(sig(ip, 150 - eps) - sig(ip, 150 + eps)) < 1e-6);

  // simulate with output samples straddling the corners
  std::vector<double> times{0,       99.999,  100, 100.001, 149.999, 150,
                            150.001, 249.999, 250, 250.001, 300,     400};
  std::vector<std::vector<double>> rows;
  std::vector<double> T = net.initial_state();
  thermnet::SolverOptions so;
  so.rtol = so.atol = 1e-10;
  thermnet::integrate(
      net, T, 0.0, 400.0, times,
      [&](double t, const std::vector<double>& x) {
        std::vector<double> all(spec.nodes.size());
        net.expand(t, x.data(), all.data());
        rows.push_back(all);
      },
      so);
  REQUIRE(rows.size() == times.size());
  auto at = [&](std::size_t k, int i) { return rows[k][static_cast<std::size_t>(i)] - kZeroC; };
  // boundaries as sampled
  CHECK(at(1, is) == doctest::Approx(20));
  CHECK(at(2, is) == doctest::Approx(50));
  CHECK(at(5, ip) == doctest::Approx(80));
  CHECK(at(8, is) == doctest::Approx(10));
  CHECK(at(10, ip) == doctest::Approx(0).scale(1));
  // node temperatures continuous across the corners: |dT| <= |G dTb / C| * 0.002 s
  double jump_s1 = std::abs(at(3, ns) - at(1, ns));
  double jump_s2 = std::abs(at(9, ns) - at(7, ns));
  double jump_p = std::abs(at(6, np) - at(4, np));
  MESSAGE("continuity: node jumps across corners " << jump_s1 << ", " << jump_s2 << ", " << jump_p
                                                   << " K over 2 ms");
  // bound: |dT/dt| <= G/C * max|Tb - T| over the 2 ms window
  auto bound = [&](std::size_t k0, std::size_t k1, int node, int b) {
    double d = std::max({std::abs(at(k0, b) - at(k0, node)), std::abs(at(k1, b) - at(k1, node))});
    return 0.01 * d * 0.002 * 1.01 + 1e-7;
  };
  CHECK(jump_s1 < bound(1, 3, ns, is));
  CHECK(jump_s2 < bound(7, 9, ns, is));
  CHECK(jump_p < bound(4, 6, np, ip));
  CHECK(jump_s1 > 0.25 * bound(1, 3, ns, is)); // and it does move (a real slope, not a frozen node)
  // analytic node under the step boundary until t = 250: T = Tb + (T(100) - Tb) e^{-(t-100)/100}
  double T100 = 20; // it stays at 20 until 100 (boundary equal to T0)
  CHECK(at(1, ns) == doctest::Approx(20).epsilon(1e-9));
  double exact249 = 50 + (T100 - 50) * std::exp(-(249.999 - 100) / 100);
  CHECK(std::abs(at(7, ns) - exact249) < 1e-6);
}

TEST_CASE("physics: a table() boundary equals the same pwl") {
  TempDir dir;
  dir.write("x.csv", "time,col,other\n0,20,0\n100,35.5,1\n250,-5,2\n400,10,3\n");
  const std::string tab = R"(
boundary b T = table("x.csv", "col")
node n C = 500 T0 = 10
conductance g n b G = 5
case c { duration = 600; output = 5 }
)";
  const std::string pwl = R"(
boundary b T = pwl(0: 20, 100: 35.5, 250: -5, 400: 10)
node n C = 500 T0 = 10
conductance g n b G = 5
case c { duration = 600; output = 5 }
)";
  Network nt(spec_from(dir, tab));
  Network np(spec_from(dir, pwl));
  SimulationResult rt = thermnet::simulate(nt, tight(1e-10));
  SimulationResult rp = thermnet::simulate(np, tight(1e-10));
  REQUIRE(rt.times.size() == rp.times.size());
  double err = 0;
  for (std::size_t k = 0; k < rt.times.size(); ++k)
    for (std::size_t i = 0; i < rt.names.size(); ++i)
      err = std::max(err, std::abs(rt.temps[k][i] - rp.temps[k][i]));
  MESSAGE("table vs pwl: max difference " << err << " K");
  CHECK(err < 1e-9);
}

TEST_CASE("physics: initial = steady starts at the steady state and does not drift") {
  const std::string text = R"(
boundary amb T = 10
node a C = 1000
node b C = 200
heater h a P = 30
conductance gab a b G = 2
conductance gb b amb G = 3
radiation r a amb GR = 0.005
case s { duration = 5000; initial = steady; output = 50 }
)";
  Network net(spec_from(text));
  SimulationResult r = thermnet::simulate(net, SimulationOptions{});
  int ia = col(r, "a"), ib = col(r, "b");
  // steady check of the first row: heater = radiation + conduction via b; b balances
  double Ta = r.temps[0][static_cast<std::size_t>(ia)],
         Tb = r.temps[0][static_cast<std::size_t>(ib)];
  double Tamb = 10 + kZeroC;
  double resid_a = 30 - 2 * (Ta - Tb) - kSigma * 0.005 * (std::pow(Ta, 4) - std::pow(Tamb, 4));
  double resid_b = 2 * (Ta - Tb) - 3 * (Tb - Tamb);
  double drift = 0;
  for (std::size_t k = 0; k < r.times.size(); ++k)
    drift = std::max({drift, std::abs(r.temps[k][static_cast<std::size_t>(ia)] - Ta),
                      std::abs(r.temps[k][static_cast<std::size_t>(ib)] - Tb)});
  MESSAGE("initial = steady: T_a " << Ta - kZeroC << " degC, residuals " << resid_a << ", "
                                   << resid_b << " W, max drift " << drift << " K");
  CHECK(std::abs(resid_a) < 1e-6);
  CHECK(std::abs(resid_b) < 1e-6);
  CHECK(Ta > Tamb + 1);
  CHECK(drift < 1e-6);
}

} // namespace
