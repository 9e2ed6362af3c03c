// The prediction criterion's building blocks: the chi-square tail of the likelihood-ratio test,
// the whiteness tests on white and autocorrelated series, Van Loan's discretisation of one node.

#include "kernel/calibration/prediction_error.hpp"
#include "kernel/calibration/whiteness.hpp"
#include "kernel/core/kalman_filter.hpp"
#include "kernel/diagnosis/report.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

using namespace thermnet;

TEST_CASE("prediction: the chi-square upper tail matches tabulated quantiles") {
  // 95 % quantiles: 3.841 (1 df), 5.991 (2), 9.488 (4); 99 %: 6.635 (1), 23.209 (10).
  CHECK(chi_square_upper(3.841459, 1) == doctest::Approx(0.05).epsilon(1e-5));
  CHECK(chi_square_upper(5.991465, 2) == doctest::Approx(0.05).epsilon(1e-5));
  CHECK(chi_square_upper(9.487729, 4) == doctest::Approx(0.05).epsilon(1e-5));
  CHECK(chi_square_upper(6.634897, 1) == doctest::Approx(0.01).epsilon(1e-5));
  CHECK(chi_square_upper(23.209251, 10) == doctest::Approx(0.01).epsilon(1e-5));
  const LikelihoodRatio lr = likelihood_ratio(100.0, 5, 104.0, 7);
  CHECK(lr.statistic == doctest::Approx(8.0));
  CHECK(lr.df == 2);
  CHECK(lr.p_value == doctest::Approx(std::exp(-4.0)).epsilon(1e-9)); // 2 df: exp(-x/2)
}

TEST_CASE("prediction: white noise passes the whiteness tests, an AR(1) series fails them") {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n01(0.0, 1.0);
  int white_pass = 0;
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> e(400);
    for (double& v : e)
      v = n01(rng);
    white_pass += test_whiteness(e, 60.0).white() ? 1 : 0;
  }
  CHECK(white_pass >= 17); // each test passes noise with about 99 % / 95 % probability
  std::vector<double> ar(400);
  double x = 0.0;
  for (double& v : ar) {
    x = 0.8 * x + n01(rng);
    v = x;
  }
  const Whiteness w = test_whiteness(ar, 60.0);
  CHECK_FALSE(w.acf_white);
  CHECK_FALSE(w.cpgram_white);
  CHECK(w.acf[1] == doctest::Approx(0.8).epsilon(0.15));
  CHECK(w.acf_peak_lag == 1);
}

TEST_CASE("prediction: Van Loan's discretisation of one node is the analytic one") {
  // dT = -T/tau dt + q dw: Phi = exp(-h/tau), Qd = q^2 tau/2 (1 - exp(-2h/tau)).
  const double tau = 500.0, q = 0.01, h = 300.0;
  const Discretised d = discretise(Eigen::MatrixXd::Constant(1, 1, -1.0 / tau),
                                   Eigen::MatrixXd::Constant(1, 1, q * q), h);
  CHECK(d.Phi(0, 0) == doctest::Approx(std::exp(-h / tau)).epsilon(1e-12));
  CHECK(d.Qd(0, 0) ==
        doctest::Approx(q * q * tau / 2 * (1 - std::exp(-2 * h / tau))).epsilon(1e-10));
  // The update's log-likelihood is that of N(0, P + R) at the innovation.
  KalmanFilter f(Eigen::VectorXd::Constant(1, 1.0), Eigen::MatrixXd::Constant(1, 1, 0.04));
  const Innovation in =
      f.update({0}, Eigen::VectorXd::Constant(1, 1.3), Eigen::VectorXd::Constant(1, 0.05));
  const double S = 0.09;
  CHECK(in.log_likelihood ==
        doctest::Approx(-0.5 * (std::log(2 * M_PI * S) + 0.09 / S)).epsilon(1e-12));
  CHECK(f.x()(0) == doctest::Approx(1.0 + 0.04 / S * 0.3));
}

TEST_CASE("prediction: a diagnosis report names its criterion, output error by default") {
  DiagnosisReport r;
  const auto j = diagnosis_json(r);
  CHECK(j["criterion"] == "output-error");
  CHECK_FALSE(j.contains("prediction"));
  CHECK(diagnosis_text(r).find("Criterion: prediction") == std::string::npos);
  DiagnosisOptions o;
  CHECK(o.criterion == "output-error");
}
