// Thermostats that behave like hardware: a sensor on another node than the heated one, a sensor
// lag and minimum on/off times, against closed-form solutions of the piecewise linear networks;
// steady states and cycling with them.

#include "kernel/core/energy_account.hpp"
#include "kernel/core/integrator.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"

#include <doctest/doctest.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "loaded_model.hpp"
#include "temp_dir.hpp"

namespace {

using namespace thermnet;

constexpr double kZeroC = 273.15;

/// The network of a model text (linted clean), for its default case.
Network network_of(const std::string& text) {
  test::TempDir dir("thermostat");
  test::LoadedModel m(dir.write("model.tnet", text), test::Lint::clean);
  return Network(m.model->instantiate());
}

/// Solver options tight enough that the numbers compared below are the solution's, not the
/// solver's: rtol = atol = 1e-10 (kelvin and seconds).
SolverOptions tight() {
  SolverOptions o;
  o.rtol = o.atol = 1e-10;
  return o;
}

/// A network that records the times at which its events changed an output (a thermostat switched).
class SwitchLog final : public ForwardingSystem {
public:
  explicit SwitchLog(Network& net) : ForwardingSystem(net) {}
  std::vector<double> times; ///< switching instants, s

  bool apply_events(double t, const double* T, const std::vector<int>& fired) override {
    const bool changed = ForwardingSystem::apply_events(t, T, fired);
    if (changed) times.push_back(t);
    return changed;
  }
};

/// x' = A x + b for two states, from x(0) = x0, in closed form. By Cayley-Hamilton each component
/// of d(t) = x(t) - x_inf (x_inf = -A^-1 b) obeys d'' = tr(A) d' - det(A) d, so
///   d_i(t) = a_i e^(l1 t) + c_i e^(l2 t),  l1,2 = (tr +- sqrt(tr^2 - 4 det)) / 2,
/// with a_i + c_i = d_i(0) and l1 a_i + l2 c_i = d_i'(0) = (A d(0))_i. (The networks below are
/// symmetric under the capacity weighting, so l1 and l2 are real, negative and distinct.)
struct TwoStates {
  double l1 = 0, l2 = 0;
  double inf[2] = {0, 0}, a[2] = {0, 0}, c[2] = {0, 0};

  TwoStates(const double A[2][2], const double b[2], const double x0[2]) {
    const double tr = A[0][0] + A[1][1], det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
    const double root = std::sqrt(tr * tr - 4 * det);
    l1 = 0.5 * (tr + root);
    l2 = 0.5 * (tr - root);
    inf[0] = -(A[1][1] * b[0] - A[0][1] * b[1]) / det;
    inf[1] = -(A[0][0] * b[1] - A[1][0] * b[0]) / det;
    const double d[2] = {x0[0] - inf[0], x0[1] - inf[1]};
    for (int i = 0; i < 2; ++i) {
      const double rate = A[i][0] * d[0] + A[i][1] * d[1];
      a[i] = (rate - l2 * d[i]) / (l1 - l2);
      c[i] = d[i] - a[i];
    }
  }
  /// Component i at t.
  double at(int i, double t) const {
    return inf[i] + a[i] * std::exp(l1 * t) + c[i] * std::exp(l2 * t);
  }
  /// When component i, rising, reaches `level` (bisection on [0, hi] of the closed form).
  double reaches(int i, double level, double hi) const {
    double lo = 0;
    REQUIRE(at(i, hi) > level);
    for (int k = 0; k < 200; ++k)
      (at(i, 0.5 * (lo + hi)) < level ? lo : hi) = 0.5 * (lo + hi);
    return hi;
  }
  /// Where component i has its extremum (d_i' = 0: l1 a e^(l1 t) = -l2 c e^(l2 t)).
  double extremum(int i) const { return std::log(-l2 * c[i] / (l1 * a[i])) / (l1 - l2); }
};

/// Integrates `net` from its initial state over [0, t1] with outputs at `times`, recording the
/// switching instants; the callback gets every unknown (internal states after the temperatures).
std::vector<double> run(Network& net, double t1, const std::vector<double>& times,
                        const OutputCallback& out) {
  SwitchLog log(net);
  std::vector<double> T = net.initial_state();
  integrate(log, T, 0.0, t1, times, out, tight());
  return log.times;
}

} // namespace

TEST_CASE("thermostat: a heater film sensed on its mount overshoots by the analytic amount") {
  // The heater film (C1 = 50 J/K) is glued to the mount (C2 = 500 J/K) by G = 2 W/K; the mount
  // loses G2 = 0.5 W/K to the 0 degC environment, and carries the sensor. Both start at 0 degC; the
  // heater (40 W) runs until the mount reaches 20 degC. The film is then ~P/G = 20 K hotter than
  // the mount, and that heat keeps flowing into the mount after the switch-off: the mount peaks
  // above 'off'. With x = T - T_amb (degC here), heating or not the network is linear,
  //   x' = A x + b,  A = [[-G/C1, G/C1], [G/C2, -(G + G2)/C2]],  b = (P/C1, 0) on, 0 off,
  // solved in closed form by TwoStates: the switch-off time t_off is where the heating solution
  // from 0 gives x_mount = 20; from the state there, the unheated mount peaks where its
  // derivative vanishes, t* = ln(-l2 c / (l1 a)) / (l1 - l2) after t_off.
  const std::string text = R"(
boundary amb T = 0
node film C = 50 T0 = 0
node mount C = 500 T0 = 0
conductance glue film mount G = 2
conductance loss mount amb G = 0.5
thermostat th film P = 40 on = 18 off = 20 sense = mount
)";
  const double C1 = 50, C2 = 500, G = 2, G2 = 0.5, P = 40, off = 20;
  const double A[2][2] = {{-G / C1, G / C1}, {G / C2, -(G + G2) / C2}};
  const double heat[2] = {P / C1, 0}, none[2] = {0, 0}, start[2] = {0, 0};
  const TwoStates heating(A, heat, start);
  const double t_off = heating.reaches(1, off, 5000);
  const double at_off[2] = {heating.at(0, t_off), heating.at(1, t_off)};
  const TwoStates cooling(A, none, at_off);
  const double t_star = cooling.extremum(1);
  const double overshoot = cooling.at(1, t_star) - off;
  REQUIRE(t_star > 0);
  MESSAGE("film/mount: switch-off at " << t_off << " s with the film at " << at_off[0]
                                       << " degC; mount peaks " << t_star << " s later, "
                                       << overshoot << " K above 'off'");

  Network net = network_of(text);
  const double t_peak = t_off + t_star;
  // Dense outputs around the peak, and the analytic peak time itself.
  std::vector<double> times;
  for (double t = t_off; t < t_peak + 100; t += 0.05)
    times.push_back(t);
  times.push_back(t_peak);
  std::sort(times.begin(), times.end());
  double mount_at_peak = 0, highest = -1e9;
  const std::vector<double> switches =
      run(net, t_peak + 100, times, [&](double t, const std::vector<double>& x) {
        const double mount = x[1] - kZeroC;
        highest = std::max(highest, mount);
        if (t == t_peak) mount_at_peak = mount;
      });
  REQUIRE(switches.size() == 1);
  MESSAGE("film/mount: switch-off time error " << switches[0] - t_off << " s, peak error "
                                               << mount_at_peak - off - overshoot
                                               << " K, highest sample " << highest - off);
  CHECK(overshoot > 0.1); // the effect is real, not a round-off
  // 1e-6 K / 1e-5 s: four orders above the solver tolerances of 1e-10 (relative to ~300 K).
  CHECK(std::abs(switches[0] - t_off) < 1e-5);
  CHECK(std::abs(mount_at_peak - off - overshoot) < 1e-6);
  CHECK(highest <= off + overshoot + 1e-6);
}

TEST_CASE("thermostat: a sensor lag delays the switch-off and overshoots by the analytic amount") {
  // One node (C = 1000 J/K, G = 10 W/K to 0 degC, P = 500 W: T_inf = 50 degC, RC = 100 s) sensed
  // through a lag of 20 s: R' = (T - R) / 20. With x = (T, R) in degC,
  //   A = [[-G/C, 0], [1/lag, -1/lag]],  b = (P/C, 0) heating, 0 not,
  // from T = R = 0 the heater stays on until R = 40 degC, when T is already hotter: T's peak is
  // T(t_off) (it falls from then on). R still rises until it meets T (R' = 0), peaking above 'off'
  // as well; it then falls and switches the heater on again below 'on' = 30 degC, when T has
  // already undershot it.
  const std::string text = R"(
boundary amb T = 0
node n C = 1000 T0 = 0
conductance g n amb G = 10
thermostat th n P = 500 on = 30 off = 40 lag = 20 [s]
)";
  const double C = 1000, G = 10, P = 500, lag = 20, on = 30, off = 40;
  const double A[2][2] = {{-G / C, 0}, {1 / lag, -1 / lag}};
  const double heat[2] = {P / C, 0}, none[2] = {0, 0}, start[2] = {0, 0};
  const TwoStates heating(A, heat, start);
  const double t_off = heating.reaches(1, off, 1000);
  const double at_off[2] = {heating.at(0, t_off), heating.at(1, t_off)};
  const TwoStates cooling(A, none, at_off);
  const double reading_peak = cooling.at(1, cooling.extremum(1));
  // Switch-on again: the reading falls to 'on' (bisection on the falling closed form).
  double lo = cooling.extremum(1), hi = 1000;
  for (int k = 0; k < 200; ++k)
    (cooling.at(1, 0.5 * (lo + hi)) > on ? lo : hi) = 0.5 * (lo + hi);
  const double t_on = t_off + hi, node_at_on = cooling.at(0, hi);
  MESSAGE("lag: off at " << t_off << " s with T = " << at_off[0] << " degC (overshoot "
                         << at_off[0] - off << " K), reading peaks at " << reading_peak
                         << " degC; on again at " << t_on << " s with T = " << node_at_on);

  Network net = network_of(text);
  REQUIRE(net.size() == 2); // the node, then the sensor's reading
  REQUIRE(net.temperature_count() == 1);
  CHECK(net.unknown_name(1) == "th.sensor");
  std::vector<double> times;
  for (double t = 0; t <= t_on + 1; t += 0.05)
    times.push_back(t);
  times.push_back(t_off);
  times.push_back(t_on);
  std::sort(times.begin(), times.end());
  double highest = -1e9, reading_highest = -1e9, node_off = 0, node_on = 0;
  const std::vector<double> switches =
      run(net, t_on + 1, times, [&](double t, const std::vector<double>& x) {
        highest = std::max(highest, x[0] - kZeroC);
        reading_highest = std::max(reading_highest, x[1] - kZeroC);
        if (t == t_off) node_off = x[0] - kZeroC;
        if (t == t_on) node_on = x[0] - kZeroC;
      });
  REQUIRE(switches.size() == 2);
  MESSAGE("lag: switching time errors " << switches[0] - t_off << ", " << switches[1] - t_on
                                        << " s; node peak error " << highest - at_off[0] << " K");
  CHECK(at_off[0] - off > 1.0);
  CHECK(std::abs(switches[0] - t_off) < 1e-5);
  CHECK(std::abs(switches[1] - t_on) < 1e-5);
  CHECK(std::abs(node_off - at_off[0]) < 1e-6);
  CHECK(std::abs(highest - at_off[0]) < 1e-6);
  CHECK(std::abs(node_on - node_at_on) < 1e-6);
  CHECK(reading_highest <= reading_peak + 1e-6);
  CHECK(reading_highest >= reading_peak - 1e-3); // sampled every 0.05 s near a smooth maximum
}

namespace {

/// The switching instants of one RC node (RC, T_inf, start T0 below 'on'; degC) under a thermostat
/// with minimum times, by a separate, algebraic route: heating or cooling is monotone, so each
/// switch comes at max(threshold crossing, end of the hold), where the crossing from T is
/// RC ln((T_inf - T) / (T_inf - off)) heating and RC ln(T / on) cooling (towards 0 degC), and the
/// hold ends min_on / min_off after the last switch (none before the first).
std::vector<double> rc_instants(double RC, double Tinf, double T0, double on, double off,
                                double min_on, double min_off, double t1) {
  std::vector<double> out;
  double t = 0, T = T0;
  bool heating = true;
  bool switched = false;
  for (;;) {
    const double cross = heating ? RC * std::log((Tinf - T) / (Tinf - off)) : RC * std::log(T / on);
    const double hold = switched ? (heating ? min_on : min_off) : 0.0;
    const double dt = std::max(std::max(cross, 0.0), hold);
    if (t + dt > t1) return out;
    T = heating ? Tinf - (Tinf - T) * std::exp(-dt / RC) : T * std::exp(-dt / RC);
    t += dt;
    out.push_back(t);
    heating = !heating;
    switched = true;
  }
}

/// Time on within [0, t1] of a heater on at 0 and toggled at `instants`.
double on_time(const std::vector<double>& instants, double t1) {
  double on = 0, since = 0;
  bool heating = true;
  for (double t : instants) {
    if (heating) on += t - since;
    since = t;
    heating = !heating;
  }
  return on + (heating ? t1 - since : 0.0);
}

} // namespace

TEST_CASE("thermostat: minimum on and off times switch at the analytic instants") {
  // RC = 100 s, T_inf = 50 degC, from 20 degC, band 30..31 degC: far narrower than what the
  // minimum times impose (60 s of heating from 30 degC ends near 39 degC), so most switches come
  // at the end of a hold, at a time event t = t_switch + min, not at a threshold.
  const double RC = 100, Tinf = 50, T0 = 20, on = 30, off = 31, t1 = 2000;
  struct Variant {
    double min_on, min_off;
  };
  for (const Variant v : {Variant{60, 60}, Variant{60, 0}, Variant{0, 60}, Variant{40, 70}}) {
    CAPTURE(v.min_on);
    CAPTURE(v.min_off);
    const std::string text = fmt::format(R"(
boundary amb T = 0
node n C = 1000 T0 = 20
conductance g n amb G = 10
thermostat th n P = 500 on = 30 off = 31 min_on = {} [s] min_off = {} [s]
)",
                                         v.min_on, v.min_off);
    const std::vector<double> expected =
        rc_instants(RC, Tinf, T0, on, off, v.min_on, v.min_off, t1);
    Network net = network_of(text);
    const std::vector<double> found = run(net, t1, {}, {});
    REQUIRE(found.size() == expected.size());
    double worst = 0;
    for (std::size_t k = 0; k < found.size(); ++k)
      worst = std::max(worst, std::abs(found[k] - expected[k]));
    MESSAGE("min_on " << v.min_on << " s, min_off " << v.min_off << " s: " << found.size()
                      << " switches, worst instant error " << worst << " s");
    // Threshold switches carry the integration error: ~rtol * 300 K per step, ~1e-6 K over the
    // run, over a slope of ~0.2 K/s (switches at the end of a hold are exact time events).
    CHECK(worst < 1e-4);

    // The energy accounting integrates the on-time as a state: exact duty, switch count, energy.
    Network again = network_of(text);
    std::vector<double> T = again.initial_state();
    EnergyTotals totals;
    integrate_with_energy(again, T, 0.0, t1, {}, {}, tight(), totals);
    const std::size_t th = 1; // elements: g, th
    const double expected_on = on_time(expected, t1);
    MESSAGE("  on " << totals.on_time[th] << " s (analytic " << expected_on << "), duty "
                    << totals.on_time[th] / t1);
    CHECK(totals.switches[th] == static_cast<int>(expected.size()));
    CHECK(std::abs(totals.on_time[th] - expected_on) < 1e-5);
    CHECK(std::abs(totals.element_energy[th][0] - 500 * expected_on) < 500 * 1e-5);
  }
  // The cycle the minimum times impose: with both at 60 s every switch after the first is held,
  // so the instants are the first switch-off plus multiples of 60 s.
  const std::vector<double> held = rc_instants(RC, Tinf, T0, on, off, 60, 60, t1);
  REQUIRE(held.size() > 10);
  for (std::size_t k = 1; k < held.size(); ++k)
    CHECK(held[k] - held[0] == doctest::Approx(60.0 * static_cast<double>(k)));
}

TEST_CASE("thermostat: steady states with a separate sensor, a lag and minimum times") {
  // The film/mount pair of above. With 40 W the heated steady state puts the mount at 80 degC
  // (P/G2), above 'off', and the unheated one at 0 degC, below 'on': no steady state, the heater
  // cycles. With 9.5 W the heated mount settles at 19 degC, inside the band: a steady state with
  // the heater on, the film at 19 + 9.5/2 = 23.75 degC, and the lagged reading equal to the mount.
  const auto model = [](double P, const std::string& extra) {
    return fmt::format(R"(
boundary amb T = 0
node film C = 50
node mount C = 500
conductance glue film mount G = 2
conductance loss mount amb G = 0.5
thermostat th film P = {} on = 18 off = 20 sense = mount {}
case c {{ duration = 1000; output = 100; initial = steady }}
)",
                       P, extra);
  };
  for (const std::string extra :
       {"", "lag = 30 [s]", "lag = 30 [s] min_on = 60 [s] min_off = 60 [s]"}) {
    CAPTURE(extra);
    Network cycling = network_of(model(40, extra));
    CHECK_THROWS_WITH_AS(start_state(cycling, tight()), doctest::Contains("cycles"), SolverError);

    Network net = network_of(model(9.5, extra));
    std::vector<double> T = start_state(net, tight());
    REQUIRE(T.size() == static_cast<std::size_t>(net.size()));
    CHECK(T[0] - kZeroC == doctest::Approx(23.75).epsilon(1e-9));
    CHECK(T[1] - kZeroC == doctest::Approx(19.0).epsilon(1e-9));
    if (net.size() == 3) CHECK(T[2] == doctest::Approx(T[1]).epsilon(1e-12)); // reading = mount
    CHECK(net.source_power(0.0, T.data()) == 9.5);
    // Started there, nothing moves and nothing switches (no hold is left over from the search).
    SwitchLog log(net);
    integrate(log, T, 0.0, 1000.0, {}, {}, tight());
    CHECK(log.times.empty());
    CHECK(T[1] - kZeroC == doctest::Approx(19.0).epsilon(1e-9));
  }
}
