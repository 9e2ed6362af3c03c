// Estimators: the TIM-AB least-squares fit, the noise filters, the sliding-window bookkeeping, the
// Kalman filter's steady-state covariance, and error bounds on synthetic experiments built from
// the bundled models (models/slab_tim_ab, models/digital_twin).

#include "kernel/core/element_registry.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"
#include "kernel/estimation/estimator.hpp"
#include "lang/csv.hpp"
#include "lang/diagnostics.hpp"
#include "lang/model.hpp"
#include "plugins/estimator/arx_fit.hpp"
#include "plugins/estimator/filters.hpp"
#include "plugins/estimator/savgol_kernel.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace {

using namespace thermnet;
using namespace thermnet::estimation;

std::unique_ptr<Estimator> make(const std::string& method, std::vector<std::string> columns,
                                const std::map<std::string, std::string>& options,
                                const lang::NetworkSpec* net = nullptr) {
  const EstimatorPlugin* p = EstimatorRegistry::global().find(method);
  REQUIRE(p != nullptr);
  EstimatorContext ctx;
  ctx.columns = std::move(columns);
  ctx.network = net;
  for (const auto& [k, v] : options)
    ctx.settings.set(k, v);
  return p->create(ctx);
}

std::unique_ptr<lang::Model> load(const std::string& path) {
  static lang::SourceManager sources;
  lang::DiagnosticEngine diags(sources);
  auto m = lang::Model::load(path, thermnet::element_catalog(), sources, diags);
  REQUIRE(m != nullptr);
  REQUIRE(diags.error_count() == 0);
  return m;
}

std::unique_ptr<lang::Model> from_text(const std::string& text) {
  static lang::SourceManager sources;
  lang::DiagnosticEngine diags(sources);
  auto m = lang::Model::from_text("mem.tnet", text, thermnet::element_catalog(), sources, diags);
  REQUIRE(diags.error_count() == 0);
  return m;
}

double metric(const Estimator& e, const std::string& name) {
  for (const auto& m : e.metrics())
    if (m.name == name) return m.value;
  FAIL("no metric " << name);
  return 0.0;
}

} // namespace

TEST_CASE("estimator settings: a list keeps the commas inside a generated name's brackets") {
  EstimatorSettings s;
  s.set("measured", "p[1,2], q ,r[3, 4],,");
  CHECK(s.list("measured") == std::vector<std::string>{"p[1,2]", "q", "r[3,4]"});
}

TEST_CASE("arx fit: exact data give the exact coefficients") {
  const double tau = 467.0, xi = 0.93;
  std::vector<double> B, C, dC, D;
  for (int i = 0; i < 500; ++i) {
    double t = i * 2.0;
    C.push_back(20 + 30 * std::sin(t / 300.0) + 0.01 * t);
    dC.push_back(0.1 * std::cos(t / 300.0) + 0.01);
    D.push_back(20 + 10 * std::sin(t / 500.0 - 0.3));
    B.push_back(tau * dC.back() + (xi + 1) * C.back() - xi * D.back());
  }
  auto c = fit_arx(B.data(), C.data(), dC.data(), D.data(), B.size());
  REQUIRE(c.ok);
  CHECK(c.tau == doctest::Approx(tau).epsilon(1e-10));
  CHECK(c.xi == doctest::Approx(xi).epsilon(1e-10));
  CHECK(arx_extrapolate(c, 10.0, 0.5, 4.0) == doctest::Approx(tau * 0.5 + (xi + 1) * 10 - xi * 4));
  // Constant data carry no information: the fit says so instead of inventing numbers.
  std::vector<double> k(50, 20.0), z(50, 0.0);
  CHECK_FALSE(fit_arx(k.data(), k.data(), z.data(), k.data(), k.size()).ok);
}

TEST_CASE("filters: Savitzky-Golay preserves polynomials up to its order, edges included") {
  auto cubic = [](double t) { return 3.0 - 2.0 * t + 0.5 * t * t - 0.02 * t * t * t; };
  auto dcubic = [](double t) { return -2.0 + t - 0.06 * t * t; };
  for (auto [n, window, dt] : {std::tuple{200, 31, 0.1}, std::tuple{20000, 9001, 0.001}}) {
    std::vector<double> y(n), v(n), s(n);
    for (int i = 0; i < n; ++i)
      y[i] = cubic(i * dt);
    savitzky_golay(y.data(), y.size(), window, 3, dt, v.data(), s.data());
    double worst_v = 0, worst_s = 0;
    for (int i = 0; i < n; ++i) {
      worst_v = std::max(worst_v, std::abs(v[i] - y[i]));
      worst_s = std::max(worst_s, std::abs(s[i] - dcubic(i * dt)));
    }
    CAPTURE(n);
    CHECK(worst_v < 1e-8);
    CHECK(worst_s < 1e-7);
  }
  // A quadratic is not preserved by order 1 (the test can fail).
  std::vector<double> y(101), v(101), s(101);
  for (int i = 0; i < 101; ++i)
    y[i] = 0.01 * i * i;
  savitzky_golay(y.data(), y.size(), 21, 1, 1.0, v.data(), s.data());
  CHECK(std::abs(v[50] - y[50]) > 0.1);
}

TEST_CASE("filters: Savitzky-Golay reduces white noise; averaging filters keep lines inside") {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.5);
  const int n = 2001;
  std::vector<double> y(n), v(n), s(n);
  for (int i = 0; i < n; ++i)
    y[i] = 10.0 + 0.01 * i + noise(rng);
  savitzky_golay(y.data(), n, 201, 3, 1.0, v.data(), s.data());
  double raw = 0, filtered = 0;
  for (int i = 0; i < n; ++i) {
    raw += std::pow(y[i] - 10.0 - 0.01 * i, 2);
    filtered += std::pow(v[i] - 10.0 - 0.01 * i, 2);
  }
  CHECK(filtered < 0.05 * raw);
  std::vector<double> line(n), out(n);
  for (int i = 0; i < n; ++i)
    line[i] = 2.0 + 0.3 * i;
  moving_average(line.data(), n, 51, out.data());
  for (int i = 0; i < n; i += 97)
    CHECK(out[i] == doctest::Approx(line[i]));
  gaussian_smooth(line.data(), n, 151, out.data());
  for (int i = 0; i < n; i += 97)
    CHECK(out[i] == doctest::Approx(line[i]));
}

TEST_CASE("filters: the tail of filter_support samples gives the same newest value and slope") {
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  const int n = 3000;
  std::vector<double> y(n);
  for (int i = 0; i < n; ++i)
    y[i] = std::sin(i * 0.004) * 50 + noise(rng);
  for (auto kind :
       {FilterKind::none, FilterKind::savgol, FilterKind::gaussian, FilterKind::moving_average}) {
    FilterSpec spec = clamp_filter({kind, 601, 3}, n);
    std::vector<double> v(n), s(n);
    apply_filter(spec, y.data(), n, 0.1, v.data(), s.data());
    std::size_t tail = filter_support(spec);
    REQUIRE(tail < static_cast<std::size_t>(n));
    std::vector<double> tv(tail), ts(tail);
    apply_filter(spec, y.data() + (n - tail), tail, 0.1, tv.data(), ts.data());
    CAPTURE(filter_name(kind));
    CHECK(tv.back() == doctest::Approx(v.back()).epsilon(1e-9));
    CHECK(ts.back() == doctest::Approx(s.back()).epsilon(1e-9));
  }
  CHECK(clamp_filter({FilterKind::savgol, 1000, 3}, 400).window == 399);
  CHECK(clamp_filter({FilterKind::savgol, 2, 3}, 400).window == 5);
}

TEST_CASE("filters: cached Savitzky-Golay kernels give the direct computation's window") {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.3);
  const int n = 4000;
  const double dt = 0.1;
  std::vector<double> y(n);
  for (int i = 0; i < n; ++i)
    y[i] = 20 + 300 * std::sin(i * 0.0015) + 0.002 * i + noise(rng);
  for (auto [window, order] :
       {std::pair{301, 3}, std::pair{3, 1}, std::pair{41, 0}, std::pair{151, 5}}) {
    SavgolKernel kernel(window, order);
    const int h = kernel.half();
    // The cache: each sample's centred value and slope, as a stream computes them.
    std::vector<double> cv(n, std::nan("")), cd(n, std::nan(""));
    for (int i = h; i + h < n; ++i)
      std::tie(cv[i], cd[i]) = kernel.centre(y.data() + (i - h));
    for (int first : {0, 517, n - 1200}) {
      const int N = 1200;
      std::vector<double> v(N), s(N), dv(N), ds(N);
      savgol_window(kernel, y.data() + first, cv.data() + first, cd.data() + first, N, dt, v.data(),
                    s.data());
      savitzky_golay(y.data() + first, N, window, order, dt, dv.data(), ds.data());
      double worst_v = 0, worst_s = 0;
      for (int i = 0; i < N; ++i) {
        worst_v = std::max(worst_v, std::abs(v[i] - dv[i]));
        worst_s = std::max(worst_s, std::abs(s[i] - ds[i]));
      }
      CAPTURE(window);
      CAPTURE(first);
      CHECK(worst_v < 1e-9);
      CHECK(worst_s < 1e-9);
      auto [nv, ns] = kernel.newest(y.data() + first + N - window);
      CHECK(nv == doctest::Approx(dv.back()).epsilon(1e-12));
      CHECK(ns / dt == doctest::Approx(ds.back()).epsilon(1e-9));
    }
  }
  // The kernels of a cubic fit reproduce a cubic and its slope exactly.
  SavgolKernel cubic(51, 3);
  std::vector<double> c(51);
  for (int i = 0; i < 51; ++i)
    c[i] = 1.0 + 0.2 * i - 0.01 * i * i + 3e-4 * i * i * i;
  auto [cv, cs] = cubic.centre(c.data());
  CHECK(cv == doctest::Approx(c[25]).epsilon(1e-12));
  CHECK(cs == doctest::Approx(0.2 - 0.02 * 25 + 9e-4 * 25 * 25).epsilon(1e-10));
  CHECK_THROWS_AS(SavgolKernel(4, 2), std::invalid_argument);
}

TEST_CASE("tim-ab: window bookkeeping, and exact estimates where the relation holds exactly") {
  // Quadratic C, D: second-order differences are exact, so the relation holds sample by sample.
  const double tau = 120.0, xi = 0.8, dt = 0.5;
  auto C = [](double t) { return 20 + 0.05 * t + 1e-4 * t * t; };
  auto dC = [](double t) { return 0.05 + 2e-4 * t; };
  auto D = [](double t) { return 20 + 0.01 * t + 3e-5 * t * t; };
  auto B = [&](double t) { return tau * dC(t) + (xi + 1) * C(t) - xi * D(t); };
  auto dB = [&](double t) { return tau * 2e-4 + (xi + 1) * dC(t) - xi * (0.01 + 6e-5 * t); };
  auto A = [&](double t) { return tau * dB(t) + (xi + 1) * B(t) - xi * C(t); };
  auto est = make("tim-ab", {"time", "A", "B", "C", "D"},
                  {{"sensors", "B,C,D"}, {"true", "A"}, {"window", "50"}, {"slide", "7"}});
  CHECK(est->output_columns() ==
        std::vector<std::string>{"A_est", "tau_hat", "xi_hat", "A_true", "A_err"});
  const int rows = 400, N = 101; // 50 s at 0.5 s: 101 samples
  int first = -1;
  for (int k = 0; k < rows; ++k) {
    double t = k * dt;
    auto out = est->push({t, A(t), B(t), C(t), D(t)});
    REQUIRE(out.size() == 1);
    CHECK(out[0].time == t);
    if (std::isnan(out[0].values[0])) {
      CHECK(first < 0);
      continue;
    }
    if (first < 0) first = k;
    CHECK(out[0].values[0] == doctest::Approx(A(t)).epsilon(1e-8));
    CHECK(out[0].values[1] == doctest::Approx(tau).epsilon(1e-8));
  }
  CHECK(first == N - 1);
  CHECK(est->finish().empty());
  CHECK(metric(*est, "windows") == 1 + (rows - N) / 7);
  CHECK(metric(*est, "estimated_rows") == rows - N + 1);
  CHECK(metric(*est, "max_abs_error") < 1e-6);

  auto full = make("tim-ab", {"time", "A", "B", "C", "D"},
                   {{"sensors", "B,C,D"}, {"true", "A"}, {"mode", "full"}});
  for (int k = 0; k < rows; ++k)
    CHECK(full->push({k * dt, A(k * dt), B(k * dt), C(k * dt), D(k * dt)}).empty());
  CHECK(full->finish().size() == rows);
  CHECK(metric(*full, "max_abs_error") < 1e-6);

  CHECK_THROWS_AS(make("tim-ab", {"time", "B", "C"}, {{"sensors", "B,C,D"}, {"window", "5"}}),
                  EstimatorError);
  CHECK_THROWS_AS(make("tim-ab", {"time", "B", "C", "D"}, {{"sensors", "B,C,D"}}),
                  EstimatorError); // realtime without a window
}

TEST_CASE("tim-ab: the realtime Savitzky-Golay path equals filtering and fitting each window") {
  // Noisy sensors; every estimate must equal the direct computation: Savitzky-Golay over the
  // whole window, least squares, relation at the newest sample (refit rows) or the last
  // coefficients with the filter's newest value (rows between refits). The record is long enough
  // for the estimator to trim its history.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-0.5, 0.5);
  const double dt = 0.5;
  const int rows = 1500, N = 201, slide = 6;
  std::vector<double> Y[3];
  for (int k = 0; k < rows; ++k) {
    double t = k * dt;
    Y[0].push_back(20 + 80 * (1 - std::exp(-t / 150)) + 5 * std::sin(t / 40) + noise(rng));
    Y[1].push_back(20 + 50 * (1 - std::exp(-t / 220)) + 2 * std::sin(t / 50) + noise(rng));
    Y[2].push_back(20 + 30 * (1 - std::exp(-t / 300)) + noise(rng));
  }
  auto est = make("tim-ab", {"time", "B", "C", "D"},
                  {{"sensors", "B,C,D"},
                   {"window", "100"},
                   {"slide", std::to_string(slide)},
                   {"filter", "savgol"},
                   {"gamma", "0.4"}});
  FilterSpec spec =
      clamp_filter({FilterKind::savgol, static_cast<int>(std::lround(0.4 * N)), 3}, N);
  ArxCoefficients coeff;
  std::vector<double> v[3], d[3];
  int checked = 0;
  for (int k = 0; k < rows; ++k) {
    auto out = est->push({k * dt, Y[0][k], Y[1][k], Y[2][k]});
    REQUIRE(out.size() == 1);
    if (k + 1 < N) {
      CHECK(std::isnan(out[0].values[0]));
      continue;
    }
    const int first = k + 1 - N;
    for (int c = 0; c < 3; ++c) {
      v[c].resize(N);
      d[c].resize(N);
      apply_filter(spec, Y[c].data() + first, N, dt, v[c].data(), d[c].data());
    }
    if (first % slide == 0) coeff = fit_arx(v[0].data(), v[1].data(), d[1].data(), v[2].data(), N);
    REQUIRE(coeff.ok);
    double direct = arx_extrapolate(coeff, v[0].back(), d[0].back(), v[1].back());
    CHECK(out[0].values[0] == doctest::Approx(direct).epsilon(1e-9));
    CHECK(out[0].values[1] == doctest::Approx(coeff.tau).epsilon(1e-9));
    ++checked;
  }
  CHECK(checked == rows - N + 1);
}

TEST_CASE("tim-ab: the study's slab, error falls with the window and stays within bounds") {
  auto model = load(std::string(THERMNET_TEST_DIR) + "/../models/slab_tim_ab/slab.tnet");
  Network net(model->instantiate("pulse"));
  SimulationOptions opt;
  opt.output = 1.0; // 1 Hz keeps the test fast
  auto r = simulate(net, opt);
  auto col = [&](const std::string& n) {
    for (std::size_t i = 0; i < r.names.size(); ++i)
      if (r.names[i] == n) return i;
    FAIL("no node " << n);
    return std::size_t{0};
  };
  std::size_t a = col("A"), b = col("B"), c = col("C"), d = col("D");
  auto run = [&](double eta) {
    auto est = make("tim-ab", {"time", "A", "B", "C", "D"},
                    {{"sensors", "B,C,D"},
                     {"true", "A"},
                     {"tau", "467"},
                     {"eta", std::to_string(eta)},
                     {"slide", "1"}});
    for (std::size_t k = 0; k < r.times.size(); ++k)
      est->push({r.times[k], r.temps[k][a] - 273.15, r.temps[k][b] - 273.15, r.temps[k][c] - 273.15,
                 r.temps[k][d] - 273.15});
    return metric(*est, "mean_relative_error");
  };
  double e02 = run(0.2), e04 = run(0.4), e1 = run(1.0);
  CHECK(e02 > e04);
  CHECK(e04 > e1);
  CHECK(e1 < 3.0); // percent
}

TEST_CASE("ekf: on a linear one-node network the covariance converges to the analytic one") {
  // C dT/dt = -G (T - Ta); measured every h with variance R; process noise q^2 K^2/s.
  const double C = 100.0, G = 2.0, h = 5.0, sr = 0.2, q = 0.05;
  auto model = from_text("boundary amb T = 10\nnode n C = 100 T0 = 10\n"
                         "conductance g n amb G = 2\ncase c { duration = 1000 }\n");
  auto spec = model->instantiate("c");
  auto est = make(
      "ekf", {"time", "n"},
      {{"sigma-meas", std::to_string(sr)}, {"process", std::to_string(q)}, {"sigma0", "3"}}, &spec);
  std::vector<double> sd;
  for (int k = 0; k < 200; ++k)
    sd.push_back(est->push({k * h, 10.0})[0].values[1]);
  const double a = G / C, phi = std::exp(-a * h), Q = q * q * (1 - phi * phi) / (2 * a),
               R = sr * sr;
  // Steady prior P solves P^2 + P (R (1 - phi^2) - Q) - Q R = 0; the posterior is P R / (P + R).
  const double bq = R * (1 - phi * phi) - Q;
  const double prior = (-bq + std::sqrt(bq * bq + 4 * Q * R)) / 2;
  const double post = prior * R / (prior + R);
  CHECK(sd.back() == doctest::Approx(std::sqrt(post)).epsilon(1e-6));
  CHECK(sd.front() > 1.5 * sd.back()); // it did converge from the initial 3 K
}

TEST_CASE("ekf: the digital twin's hidden lens centres within 1 K, worse with fewer sensors") {
  const std::string dir = std::string(THERMNET_TEST_DIR) + "/../models/digital_twin/";
  auto model = load(dir + "twin.tnet");
  auto spec = model->instantiate("known");
  auto data = lang::read_csv(dir + "twin_data.csv");
  auto run = [&](const std::string& measured, bool smooth) {
    auto est = make("ekf", data.columns,
                    {{"measured", measured}, {"smooth", smooth ? "yes" : "no"}}, &spec);
    std::vector<double> row(data.columns.size());
    std::size_t produced = 0;
    for (std::size_t k = 0; k < data.rows(); ++k) {
      for (std::size_t c = 0; c < row.size(); ++c)
        row[c] = data.cells[c][k];
      produced += est->push(row).size();
    }
    produced += est->finish().size();
    CHECK(produced == data.rows());
    return std::pair{metric(*est, "rmse_l1_centre"), metric(*est, "rmse_l2_centre")};
  };
  auto six = run("window,l1_edge,l2_edge,barrel,inner,outer", false);
  auto smooth = run("window,l1_edge,l2_edge,barrel,inner,outer", true);
  auto barrel = run("barrel", false);
  auto outer = run("outer", false);
  CHECK(six.first < 1.0);
  CHECK(six.second < 1.0);
  CHECK(smooth.first < 1.0);
  CHECK(barrel.first > six.first);
  CHECK(barrel.second > six.second);
  CHECK(outer.first > 2.0);
}
