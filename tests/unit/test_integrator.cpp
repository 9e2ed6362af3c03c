// Unit tests of integrate() and solve_steady() on small hand-written thermal systems.

#include "kernel/core/integrator.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

using thermnet::LinearSolverKind;
using thermnet::SolverError;
using thermnet::SolverOptions;
using thermnet::SolverStats;
using thermnet::SparsityPattern;

constexpr double kZeroCelsius = 273.15;
constexpr double kSigma = 5.670374419e-8;

/// A lumped network for tests: conductances between nodes and to fixed sinks, radiation to a
/// sink, time-dependent heat sources, declared breakpoints and a hook to corrupt F.
class TestNetwork : public thermnet::ThermalSystem {
public:
  /// A network of nodes with the given capacities (0: algebraic), named n0, n1, ...
  explicit TestNetwork(std::vector<double> caps) : caps_(std::move(caps)) {
    const int n = size();
    for (int i = 0; i < n; ++i)
      names_.push_back(std::string(1, 'n').append(std::to_string(i)));
    sources_.resize(caps_.size());
  }
  /// Conductance g (W/K) between nodes i and j.
  void link(int i, int j, double g) { links_.push_back({i, j, g}); }
  /// Conductance g (W/K) from node i to a fixed temperature ts (K).
  void to_sink(int i, double g, double ts) { sinks_.push_back({i, g, ts}); }
  /// Radiation k (T_s^4 - T_i^4), k = sigma eps A in W/K^4, from node i to a sink at ts (K).
  void radiate(int i, double k, double ts) { rads_.push_back({i, k, ts}); }
  /// Heat source p(t) (W) into node i.
  void source(int i, std::function<double(double)> p) {
    sources_[static_cast<std::size_t>(i)] = std::move(p);
  }
  /// Renames node i.
  void name(int i, std::string s) { names_[static_cast<std::size_t>(i)] = std::move(s); }
  std::vector<double> break_times;                            ///< breakpoints to declare
  std::function<void(double, const double*, double*)> tamper; ///< may overwrite F

  /// Builds the CSR pattern; call after adding elements.
  void finalize() {
    const int n = size();
    std::vector<std::set<int>> rows(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i)
      rows[static_cast<std::size_t>(i)].insert(i);
    for (const Link& l : links_) {
      rows[static_cast<std::size_t>(l.i)].insert(l.j);
      rows[static_cast<std::size_t>(l.j)].insert(l.i);
    }
    pattern_.n = n;
    pattern_.row_ptr.assign(1, 0);
    pattern_.col_idx.clear();
    std::map<std::pair<int, int>, int> pos;
    for (int i = 0; i < n; ++i) {
      for (int j : rows[static_cast<std::size_t>(i)]) {
        pos[{i, j}] = static_cast<int>(pattern_.col_idx.size());
        pattern_.col_idx.push_back(j);
      }
      pattern_.row_ptr.push_back(static_cast<int>(pattern_.col_idx.size()));
    }
    link_pos_.clear();
    for (const Link& l : links_)
      link_pos_.push_back({pos[{l.i, l.i}], pos[{l.i, l.j}], pos[{l.j, l.j}], pos[{l.j, l.i}]});
    diag_pos_.clear();
    for (int i = 0; i < n; ++i)
      diag_pos_.push_back(pos[{i, i}]);
  }

  int size() const override { return static_cast<int>(caps_.size()); }
  const std::vector<double>& capacities() const override { return caps_; }
  void heat_balance(double t, const double* T, double* F) override {
    const int n = size();
    for (int i = 0; i < n; ++i) {
      const auto& p = sources_[static_cast<std::size_t>(i)];
      F[i] = p ? p(t) : 0.0;
    }
    for (const Link& l : links_) {
      const double q = l.g * (T[l.j] - T[l.i]);
      F[l.i] += q;
      F[l.j] -= q;
    }
    for (const Sink& s : sinks_)
      F[s.i] += s.g * (s.ts - T[s.i]);
    for (const Sink& r : rads_)
      F[r.i] += r.g * (std::pow(r.ts, 4) - std::pow(T[r.i], 4));
    if (tamper) tamper(t, T, F);
  }
  const SparsityPattern& jacobian_pattern() const override { return pattern_; }
  void jacobian(double /*t*/, const double* T, double* v) override {
    std::fill(v, v + pattern_.nnz(), 0.0);
    for (std::size_t k = 0; k < links_.size(); ++k) {
      const double g = links_[k].g;
      const auto& p = link_pos_[k];
      v[p[0]] -= g;
      v[p[1]] += g;
      v[p[2]] -= g;
      v[p[3]] += g;
    }
    for (const Sink& s : sinks_)
      v[diag_pos_[static_cast<std::size_t>(s.i)]] -= s.g;
    for (const Sink& r : rads_)
      v[diag_pos_[static_cast<std::size_t>(r.i)]] -= 4.0 * r.g * std::pow(T[r.i], 3);
  }
  std::vector<double> breakpoints(double t0, double t1) const override {
    std::vector<double> b;
    for (double x : break_times)
      if (x > t0 && x <= t1) b.push_back(x);
    return b;
  }
  std::string unknown_name(int i) const override { return names_[static_cast<std::size_t>(i)]; }

private:
  struct Link {
    int i, j;
    double g;
  };
  struct Sink {
    int i;
    double g, ts;
  };
  std::vector<double> caps_;
  std::vector<std::string> names_;
  std::vector<Link> links_;
  std::vector<Sink> sinks_;
  std::vector<Sink> rads_;
  std::vector<std::function<double(double)>> sources_;
  SparsityPattern pattern_;
  std::vector<std::array<int, 4>> link_pos_;
  std::vector<int> diag_pos_;
};

/// One node, capacity C, conductance G to a sink at Ts, heater P switched by a thermostat with
/// hysteresis: on below t_on, off above t_off (one event function, re-armed at each switch).
class Thermostat : public TestNetwork {
public:
  Thermostat(double c, double g, double ts, double p, double t_on, double t_off)
      : TestNetwork({c}), t_on_(t_on), t_off_(t_off) {
    to_sink(0, g, ts);
    source(0, [this, p](double) { return on_ ? p : 0.0; });
    finalize();
  }
  int event_count() const override { return 1; }
  void events(double, const double* T, double* g) override {
    g[0] = on_ ? T[0] - t_off_ : T[0] - t_on_;
  }
  bool apply_events(double t, const double*, const std::vector<int>& fired) override {
    if (fired[0] == 0) return false;
    on_ = !on_;
    switches.push_back(t);
    return true;
  }
  void init_events(double, const double* T) override { on_ = T[0] < t_off_; }
  std::vector<double> switches; ///< times of the switches

private:
  double t_on_, t_off_;
  bool on_ = false;
};

const std::vector<LinearSolverKind> kAllSolvers = {LinearSolverKind::dense, LinearSolverKind::klu,
                                                   LinearSolverKind::krylov};

const char* kind_name(LinearSolverKind k) {
  switch (k) {
  case LinearSolverKind::dense:
    return "dense";
  case LinearSolverKind::klu:
    return "klu";
  case LinearSolverKind::krylov:
    return "spgmr";
  default:
    return "automatic";
  }
}

std::vector<double> linspace(double a, double b, int n) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i)
    v.push_back(a + (b - a) * i / (n - 1));
  return v;
}

/// A chain of n nodes: heater on node 0, conductance to a 20 °C sink at the far end.
TestNetwork make_chain(int n) {
  std::vector<double> caps;
  for (int i = 0; i < n; ++i)
    caps.push_back(50.0 + 10.0 * (i % 7));
  TestNetwork net(caps);
  for (int i = 0; i + 1 < n; ++i)
    net.link(i, i + 1, 2.0 + (i % 3));
  net.to_sink(n - 1, 5.0, kZeroCelsius + 20.0);
  net.source(0, [](double) { return 50.0; });
  net.finalize();
  return net;
}

} // namespace

TEST_CASE("integrate: one-node RC decay matches exp(-t/RC) with every linear solver") {
  const double c = 1000.0, g = 2.0, ts = kZeroCelsius + 20.0, t0k = kZeroCelsius + 120.0;
  const double tau = c / g;
  for (LinearSolverKind kind : kAllSolvers) {
    CAPTURE(kind_name(kind));
    TestNetwork net({c});
    net.to_sink(0, g, ts);
    net.finalize();
    std::vector<double> T{t0k};
    SolverOptions opt;
    opt.linear_solver = kind;
    opt.rtol = 1e-9;
    opt.atol = 1e-9;
    const std::vector<double> times = linspace(0.0, 5000.0, 201);
    std::vector<double> seen;
    double worst = 0.0;
    const SolverStats st = thermnet::integrate(
        net, T, 0.0, 5000.0, times,
        [&](double t, const std::vector<double>& y) {
          seen.push_back(t);
          worst = std::max(worst, std::abs(y[0] - (ts + (t0k - ts) * std::exp(-t / tau))));
        },
        opt);
    CHECK(seen == times);
    CHECK(worst < 1e-5);
    CHECK(std::abs(T[0] - (ts + (t0k - ts) * std::exp(-5000.0 / tau))) < 1e-5);
    CHECK(st.integrator == "cvode-bdf");
    CHECK(st.linear_solver == kind_name(kind));
  }
}

TEST_CASE("integrate: default tolerances stay within a few millikelvin on RC decay") {
  TestNetwork net({1000.0});
  net.to_sink(0, 2.0, 293.15);
  net.finalize();
  std::vector<double> T{393.15};
  double worst = 0.0;
  thermnet::integrate(
      net, T, 0.0, 5000.0, linspace(0.0, 5000.0, 51), [&](double t, const std::vector<double>& y) {
        worst = std::max(worst, std::abs(y[0] - (293.15 + 100.0 * std::exp(-t / 500.0))));
      });
  CHECK(worst < 5e-3);
}

TEST_CASE("integrate: outputs are emitted once each, in order, within [t0, t1]") {
  TestNetwork net({100.0});
  net.to_sink(0, 1.0, 300.0);
  net.break_times = {5.0};
  net.finalize();
  std::vector<double> T{350.0};
  std::vector<double> seen;
  std::vector<double> values;
  const std::vector<double> times{-1.0, 0.0, 2.5, 5.0, 5.0, 7.0, 10.0, 11.0};
  thermnet::integrate(net, T, 0.0, 10.0, times, [&](double t, const std::vector<double>& y) {
    seen.push_back(t);
    values.push_back(y[0]);
  });
  CHECK(seen == std::vector<double>{0.0, 2.5, 5.0, 5.0, 7.0, 10.0});
  CHECK(values.front() == 350.0);
  CHECK(values.back() == T[0]);
  CHECK(values[2] == values[3]);
}

TEST_CASE("integrate: an algebraic node between two capacities equals the series conductance") {
  const double c1 = 1000.0, c2 = 2000.0, g1 = 5.0, g2 = 10.0;
  const double g = g1 * g2 / (g1 + g2);
  const double ta0 = 350.0, tb0 = 300.0;
  const double mean = (c1 * ta0 + c2 * tb0) / (c1 + c2);
  const double rate = g * (1.0 / c1 + 1.0 / c2);
  const auto exact = [&](double t) {
    const double d = (ta0 - tb0) * std::exp(-rate * t);
    const double ta = mean + c2 / (c1 + c2) * d;
    const double tb = mean - c1 / (c1 + c2) * d;
    return std::array<double, 3>{ta, (g1 * ta + g2 * tb) / (g1 + g2), tb};
  };
  for (LinearSolverKind kind : kAllSolvers) {
    CAPTURE(kind_name(kind));
    TestNetwork net({c1, 0.0, c2});
    net.link(0, 1, g1);
    net.link(1, 2, g2);
    net.finalize();
    std::vector<double> T{ta0, 0.0, tb0}; // the algebraic guess is made consistent by IDACalcIC
    SolverOptions opt;
    opt.linear_solver = kind;
    opt.rtol = 1e-9;
    opt.atol = 1e-9;
    double worst = 0.0;
    int calls = 0;
    const SolverStats st = thermnet::integrate(
        net, T, 0.0, 2000.0, linspace(0.0, 2000.0, 81),
        [&](double t, const std::vector<double>& y) {
          ++calls;
          const auto e = exact(t);
          for (int i = 0; i < 3; ++i)
            worst = std::max(
                worst, std::abs(y[static_cast<std::size_t>(i)] - e[static_cast<std::size_t>(i)]));
        },
        opt);
    CHECK(calls == 81);
    CHECK(worst < 1e-5);
    CHECK(st.integrator == "ida");
    CHECK(st.linear_solver == kind_name(kind));
  }
}

TEST_CASE("integrate: a step input at a breakpoint is resolved exactly") {
  const double c = 500.0, g = 1.0, ts = 300.0, t0k = 350.0, p1 = 40.0;
  const double tau = c / g;
  const auto before = [&](double t) { return ts + (t0k - ts) * std::exp(-t / tau); };
  const auto after = [&](double t) {
    const double tinf = ts + p1 / g;
    return tinf + (before(100.0) - tinf) * std::exp(-(t - 100.0) / tau);
  };
  const std::vector<double> times{50.0, 99.0, 99.999, 100.0, 100.001, 101.0, 150.0, 300.0};
  for (bool inclusive : {true, false}) { // step(t >= 100) and step(t > 100) conventions
    CAPTURE(inclusive);
    const auto run = [&](double p, const SolverOptions& opt, SolverStats* st) {
      TestNetwork net({c});
      net.to_sink(0, g, ts);
      net.source(0, [=](double t) { return (inclusive ? t >= 100.0 : t > 100.0) ? p : 0.0; });
      net.break_times = {100.0};
      net.finalize();
      std::vector<double> T{t0k};
      std::map<double, double> got;
      const SolverStats s = thermnet::integrate(
          net, T, 0.0, 300.0, times, [&](double t, const std::vector<double>& y) { got[t] = y[0]; },
          opt);
      if (st != nullptr) *st = s;
      return got;
    };
    // Up to the step the input is zero: the trajectory must not see the step at all, to the bit,
    // whatever the tolerances (a step straddling t = 100 would see it).
    for (double tol : {1e-6, 1e-10}) {
      CAPTURE(tol);
      SolverOptions opt;
      opt.rtol = tol;
      opt.atol = tol;
      SolverStats st;
      const auto with_step = run(p1, opt, &st);
      const auto without = run(0.0, opt, nullptr);
      REQUIRE(with_step.size() == times.size());
      for (double t : {50.0, 99.0, 99.999, 100.0}) {
        CAPTURE(t);
        CHECK(with_step.at(t) == without.at(t));
      }
      CHECK(with_step.at(100.001) != without.at(100.001));
      CHECK(st.restarts == 1);
      if (tol == 1e-10) {
        CHECK(std::abs(with_step.at(100.0) - before(100.0)) < 1e-6);
        CHECK(std::abs(with_step.at(100.001) - after(100.001)) < 1e-6);
        CHECK(std::abs(with_step.at(150.0) - after(150.0)) < 1e-6);
        CHECK(std::abs(with_step.at(300.0) - after(300.0)) < 1e-6);
      }
    }
  }
}

TEST_CASE("integrate: an arithmetic node jumps at a breakpoint (IDA restart with IDACalcIC)") {
  // Node 0: capacity to a sink; node 1: massless, heated by a step, conductance to node 0.
  const double c = 1000.0, g0 = 2.0, g01 = 5.0, ts = 300.0, p1 = 50.0;
  const double tau = c / g0;
  TestNetwork net({c, 0.0});
  net.to_sink(0, g0, ts);
  net.link(0, 1, g01);
  net.source(1, [=](double t) { return t >= 100.0 ? p1 : 0.0; });
  net.break_times = {100.0};
  net.finalize();
  std::vector<double> T{ts + 20.0, 0.0};
  SolverOptions opt;
  opt.rtol = 1e-10;
  opt.atol = 1e-10;
  std::map<double, std::vector<double>> got;
  const SolverStats st = thermnet::integrate(
      net, T, 0.0, 200.0, {0.0, 100.0, 100.000001, 200.0},
      [&](double t, const std::vector<double>& y) { got[t] = y; }, opt);
  const double ta100 = ts + 20.0 * std::exp(-100.0 / tau);
  CHECK(std::abs(got.at(0.0)[1] - (ts + 20.0)) < 1e-9); // consistent initial condition
  CHECK(std::abs(got.at(100.0)[0] - ta100) < 1e-6);     // left limit at the breakpoint
  CHECK(std::abs(got.at(100.0)[1] - ta100) < 1e-6);     // no heat yet: T1 = T0
  CHECK(std::abs(got.at(100.000001)[1] - (ta100 + p1 / g01)) < 1e-4); // jumped by P/G
  const double tinf = ts + p1 / g0;
  const double ta200 = tinf + (ta100 - tinf) * std::exp(-100.0 / tau);
  CHECK(std::abs(T[0] - ta200) < 1e-6);
  CHECK(std::abs(T[1] - (ta200 + p1 / g01)) < 1e-6);
  CHECK(st.integrator == "ida");
  CHECK(st.restarts == 1);
}

TEST_CASE("integrate: thermostat switching times come from root-finding") {
  const double c = 2000.0, g = 4.0, ts = kZeroCelsius, p = 400.0;
  const double t_on = kZeroCelsius + 60.0, t_off = kZeroCelsius + 70.0;
  const double rc = c / g, tinf = ts + p / g;
  Thermostat th(c, g, ts, p, t_on, t_off);
  std::vector<double> T{ts};
  SolverOptions opt;
  opt.rtol = 1e-10;
  opt.atol = 1e-10;
  const std::vector<double> times = linspace(0.0, 5000.0, 501);
  std::vector<double> seen;
  double lowest = 1e9, highest = 0.0;
  const SolverStats st = thermnet::integrate(
      th, T, 0.0, 5000.0, times,
      [&](double t, const std::vector<double>& y) {
        seen.push_back(t);
        if (t > 1000.0) { // once cycling, the temperature stays inside the hysteresis band
          lowest = std::min(lowest, y[0]);
          highest = std::max(highest, y[0]);
        }
      },
      opt);
  CHECK(seen == times);
  CHECK(lowest > t_on - 1e-6);
  CHECK(highest < t_off + 1e-6);
  CHECK(highest - lowest > 0.9 * (t_off - t_on));

  std::vector<double> expected;
  double t = rc * std::log((tinf - ts) / (tinf - t_off)); // heating from 0 °C to t_off
  while (t < 5000.0) {
    expected.push_back(t);
    t += rc * std::log((t_off - ts) / (t_on - ts)); // cooling t_off -> t_on
    if (t >= 5000.0) break;
    expected.push_back(t);
    t += rc * std::log((tinf - t_on) / (tinf - t_off)); // heating t_on -> t_off
  }
  REQUIRE(expected.size() >= 5);
  REQUIRE(th.switches.size() == expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k) {
    CAPTURE(k);
    CHECK(std::abs(th.switches[k] - expected[k]) < 1e-3);
  }
  CHECK(st.events == static_cast<long>(expected.size()));
  CHECK(st.restarts == static_cast<long>(expected.size()));
}

TEST_CASE("integrate: thermostat events work through IDA with an arithmetic node too") {
  const double c = 2000.0, g = 4.0, ts = kZeroCelsius, p = 400.0;
  const double t_on = kZeroCelsius + 60.0, t_off = kZeroCelsius + 70.0;
  // Node 0 carries the capacity; node 1 is a massless skin between it and two conductances to
  // the sink whose series value is g.
  class SkinThermostat : public TestNetwork {
  public:
    SkinThermostat(double c, double g, double ts, double p, double lower, double upper)
        : TestNetwork({c, 0.0}), on_t(lower), off_t(upper) {
      link(0, 1, 2.0 * g);
      to_sink(1, 2.0 * g, ts);
      source(0, [this, p](double) { return on ? p : 0.0; });
      finalize();
    }
    int event_count() const override { return 1; }
    void events(double, const double* T, double* gv) override {
      gv[0] = on ? T[0] - off_t : T[0] - on_t;
    }
    bool apply_events(double t, const double*, const std::vector<int>& f) override {
      if (f[0] == 0) return false;
      on = !on;
      switches.push_back(t);
      return true;
    }
    void init_events(double, const double* T) override { on = T[0] < off_t; }
    double on_t, off_t;
    bool on = false;
    std::vector<double> switches;
  };
  SkinThermostat th(c, g, ts, p, t_on, t_off);
  std::vector<double> T{ts, ts};
  SolverOptions opt;
  opt.rtol = 1e-10;
  opt.atol = 1e-10;
  const SolverStats st = thermnet::integrate(th, T, 0.0, 2000.0, {}, nullptr, opt);
  const double rc = c / g, tinf = ts + p / g;
  const double first = rc * std::log((tinf - ts) / (tinf - t_off));
  const double second = first + rc * std::log((t_off - ts) / (t_on - ts));
  REQUIRE(th.switches.size() >= 2);
  CHECK(std::abs(th.switches[0] - first) < 1e-3);
  CHECK(std::abs(th.switches[1] - second) < 1e-3);
  CHECK(st.integrator == "ida");
  CHECK(st.events == static_cast<long>(th.switches.size()));
}

TEST_CASE("integrate: a thermostat without hysteresis is stopped with a clear error") {
  const double t_set = kZeroCelsius + 60.0;
  Thermostat th(2000.0, 4.0, kZeroCelsius, 400.0, t_set, t_set);
  std::vector<double> T{kZeroCelsius};
  try {
    thermnet::integrate(th, T, 0.0, 5000.0, {}, nullptr);
    FAIL("expected SolverError");
  } catch (const SolverError& e) {
    const std::string what = e.what();
    CAPTURE(what);
    CHECK(what.find("events keep firing") != std::string::npos);
    CHECK(e.time > 100.0);
    CHECK(e.time < 600.0);
  }
}

TEST_CASE("solve_steady: conduction then radiation (T^4) matches the closed form") {
  const double p = 100.0, g = 2.0, k = kSigma * 0.9 * 0.5, ts = 250.0;
  const double t2 = std::pow(std::pow(ts, 4) + p / k, 0.25);
  const double t1 = t2 + p / g;
  for (LinearSolverKind kind : kAllSolvers) {
    CAPTURE(kind_name(kind));
    TestNetwork net({10.0, 0.0});
    net.source(0, [=](double) { return p; });
    net.link(0, 1, g);
    net.radiate(1, k, ts);
    net.finalize();
    std::vector<double> T{300.0, 300.0};
    SolverOptions opt;
    opt.linear_solver = kind;
    const SolverStats st = thermnet::solve_steady(net, T, 0.0, opt);
    CHECK(std::abs(T[0] - t1) < 1e-7 * t1);
    CHECK(std::abs(T[1] - t2) < 1e-7 * t2);
    CHECK(st.integrator == "kinsol");
    CHECK(st.steps > 0);
    CHECK(st.jac_evals > 0);
    CHECK(st.linear_solver == (kind == LinearSolverKind::dense ? "dense" : "klu"));
  }
}

TEST_CASE("solve_steady: a floating node gives a SolverError naming it") {
  TestNetwork net({10.0, 10.0, 10.0});
  net.link(0, 1, 1.0);
  net.to_sink(1, 1.0, 300.0);
  net.source(2, [](double) { return 5.0; }); // node 2 has no path anywhere
  net.name(2, "orphan");
  net.finalize();
  std::vector<double> T{300.0, 300.0, 300.0};
  try {
    thermnet::solve_steady(net, T, 0.0);
    FAIL("expected SolverError");
  } catch (const SolverError& e) {
    const std::string what = e.what();
    CAPTURE(what);
    CHECK(what.find("KINSOL failed") != std::string::npos);
    CHECK(what.find("orphan") != std::string::npos);
    CHECK(what.find("no conductance") != std::string::npos);
    CHECK(e.call == "KINSol");
  }
}

TEST_CASE("integrate: an arithmetic node coupled to nothing gives a SolverError naming it") {
  TestNetwork net({10.0, 0.0});
  net.to_sink(0, 1.0, 300.0);
  net.name(1, "loose");
  net.finalize();
  std::vector<double> T{310.0, 300.0};
  try {
    thermnet::integrate(net, T, 0.0, 10.0, {}, nullptr);
    FAIL("expected SolverError");
  } catch (const SolverError& e) {
    const std::string what = e.what();
    CAPTURE(what);
    CHECK(what.find("IDA failed at t = 0 s") == 0);
    CHECK(what.find("loose") != std::string::npos);
  }
}

TEST_CASE("integrate: a 20,000-node chain gives the same answer with KLU and SPGMR") {
  const int n = 20000;
  std::vector<std::vector<double>> results;
  std::vector<std::vector<double>> probes;
  for (LinearSolverKind kind : {LinearSolverKind::klu, LinearSolverKind::krylov}) {
    CAPTURE(kind_name(kind));
    TestNetwork net = make_chain(n);
    std::vector<double> T(static_cast<std::size_t>(n), kZeroCelsius + 20.0);
    SolverOptions opt;
    opt.linear_solver = kind;
    opt.rtol = 1e-8;
    opt.atol = 1e-8;
    std::vector<double> probe;
    const SolverStats st = thermnet::integrate(
        net, T, 0.0, 2000.0, {500.0, 1000.0, 2000.0},
        [&](double, const std::vector<double>& y) {
          probe.push_back(y[0]);
          probe.push_back(y[10]);
          probe.push_back(y[100]);
        },
        opt);
    CHECK(st.linear_solver == kind_name(kind));
    CHECK(T[0] > kZeroCelsius + 20.5);
    results.push_back(T);
    probes.push_back(probe);
  }
  double worst = 0.0;
  for (std::size_t i = 0; i < results[0].size(); ++i)
    worst = std::max(worst, std::abs(results[0][i] - results[1][i]));
  CHECK(worst < 1e-3); // both within their own time-stepping error (~2e-4 K here) of the truth
  REQUIRE(probes[0].size() == probes[1].size());
  for (std::size_t i = 0; i < probes[0].size(); ++i)
    CHECK(std::abs(probes[0][i] - probes[1][i]) < 1e-3);
}

TEST_CASE(
    "integrate: automatic picks dense for small, KLU for medium and Krylov for large systems") {
  TestNetwork small = make_chain(10);
  std::vector<double> T(10, 300.0);
  CHECK(thermnet::integrate(small, T, 0.0, 10.0, {}, nullptr).linear_solver == "dense");
  TestNetwork medium = make_chain(300);
  std::vector<double> T2(300, 300.0);
  CHECK(thermnet::integrate(medium, T2, 0.0, 10.0, {}, nullptr).linear_solver == "klu");
  TestNetwork large = make_chain(3000);
  std::vector<double> T3(3000, 300.0);
  CHECK(thermnet::integrate(large, T3, 0.0, 10.0, {}, nullptr).linear_solver == "spgmr");
}

TEST_CASE("integrate: a heat balance turning NaN gives a SolverError with time and node") {
  for (bool algebraic : {false, true}) {
    CAPTURE(algebraic);
    TestNetwork net({100.0, algebraic ? 0.0 : 50.0, 100.0});
    net.link(0, 1, 1.0);
    net.link(1, 2, 1.0);
    net.to_sink(2, 1.0, 300.0);
    net.source(0, [](double) { return 20.0; });
    net.name(0, "heater");
    net.name(1, "hot");
    net.name(2, "wall");
    net.tamper = [](double t, const double*, double* F) {
      if (t > 50.0) F[1] = std::numeric_limits<double>::quiet_NaN();
    };
    net.finalize();
    std::vector<double> T{300.0, 300.0, 300.0};
    try {
      thermnet::integrate(net, T, 0.0, 200.0, {10.0, 100.0},
                          [](double, const std::vector<double>&) {});
      FAIL("expected SolverError");
    } catch (const SolverError& e) {
      const std::string what = e.what();
      CAPTURE(what);
      CHECK(what.find(algebraic ? "IDA failed at t = " : "CVODE failed at t = ") == 0);
      CHECK(what.find("hot") != std::string::npos);
      CHECK(what.find("not finite") != std::string::npos);
      CHECK(e.time > 40.0);
      CHECK(e.time <= 50.0 + 1e-6);
      REQUIRE(!e.worst.empty());
      CHECK(e.worst.front() == "hot");
      CHECK(T[0] > 300.0); // T holds the last state reached
    }
  }
}

TEST_CASE("integrate: exceptions thrown by the system propagate unchanged") {
  TestNetwork net({100.0});
  net.to_sink(0, 1.0, 300.0);
  net.tamper = [](double t, const double*, double*) {
    if (t > 5.0) throw std::domain_error("table lookup out of range");
  };
  net.finalize();
  std::vector<double> T{310.0};
  CHECK_THROWS_AS(thermnet::integrate(net, T, 0.0, 10.0, {}, nullptr), std::domain_error);
}

TEST_CASE("integrate: max_steps exceeded is a SolverError") {
  TestNetwork net = make_chain(5);
  std::vector<double> T(5, 300.0);
  SolverOptions opt;
  opt.max_steps = 10;
  try {
    thermnet::integrate(net, T, 0.0, 1e5, {}, nullptr, opt);
    FAIL("expected SolverError");
  } catch (const SolverError& e) {
    const std::string what = e.what();
    CAPTURE(what);
    CHECK(what.find("max_steps") != std::string::npos);
    CHECK(what.find("CV_TOO_MUCH_WORK") != std::string::npos);
    CHECK(e.time > 0.0);
  }
}

TEST_CASE("integrate: stats counters are populated") {
  TestNetwork net = make_chain(24);
  net.break_times = {1000.0, 2000.0};
  std::vector<double> T(24, 300.0);
  SolverOptions opt;
  opt.max_step = 500.0;
  const SolverStats st = thermnet::integrate(net, T, 0.0, 10000.0, {}, nullptr, opt);
  CHECK(st.integrator == "cvode-bdf");
  CHECK(st.linear_solver == "dense");
  CHECK(st.steps >= 20); // max_step forces at least 10000 / 500 steps
  CHECK(st.rhs_evals > st.steps);
  CHECK(st.jac_evals > 0);
  CHECK(st.linear_setups > 0);
  CHECK(st.nonlinear_iters >= st.steps);
  CHECK(st.restarts == 2);
  CHECK(st.events == 0);
}
