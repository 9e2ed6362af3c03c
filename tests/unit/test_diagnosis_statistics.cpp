// Unit tests of the diagnosis's statistics (autocorrelation time, the comparison of two fits, the
// held-out gain test against the noise floor) and of the report's ambiguity set.

#include "kernel/diagnosis/report.hpp"
#include "kernel/diagnosis/statistics.hpp"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <random>
#include <string>
#include <vector>

using namespace thermnet;

TEST_CASE("diagnosis statistics: autocorrelation time and the comparison of two fits") {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 0.1);
  std::vector<std::vector<double>> white(4), ar(4);
  for (int s = 0; s < 4; ++s) {
    double x = 0.0;
    for (int k = 0; k < 2000; ++k) {
      white[s].push_back(noise(rng));
      x = 0.8 * x + noise(rng);
      ar[s].push_back(x);
    }
  }
  CHECK(autocorrelation_time(white) == doctest::Approx(1.0).epsilon(0.1));
  CHECK(autocorrelation_time(ar) == doctest::Approx(9.0).epsilon(0.2));
  // Two fits whose residuals differ by a tiny systematic amount: not told apart.
  std::vector<StoredResiduals> stored; // (the fits' residuals as the diagnosis keeps them)
  for (const auto& v : white)
    stored.emplace_back(v.begin(), v.end());
  FitResiduals a{stored, 1.0}, b{stored, 1.01};
  for (auto& v : b.series)
    for (std::size_t k = 0; k < v.size(); ++k)
      v[k] += static_cast<float>(0.003 * std::sin(static_cast<double>(k) / 50.0));
  const FitComparison same = compare_fits(a, b, 0.1);
  CHECK(same.z < 3.0);
  CHECK_FALSE(same.separable);
  // A systematic error of the second fit as large as the noise: told apart, the first is better.
  for (auto& v : b.series)
    for (std::size_t k = 0; k < v.size(); ++k)
      v[k] += static_cast<float>(0.1 * std::sin(static_cast<double>(k) / 50.0));
  const FitComparison apart = compare_fits(a, b, 0.1);
  CHECK(apart.first_better);
  CHECK(apart.separable);
  // ... but not when the held-out data disagree.
  b.holdout_sse = 0.5;
  CHECK_FALSE(compare_fits(a, b, 0.1).separable);
}

TEST_CASE("diagnosis statistics: the held-out gain test against the noise floor") {
  // Held-out residuals: a reference fit with a systematic error, candidates that remove some of
  // it, all with the same white noise (sigma 0.3 K).
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 0.3);
  const std::size_t n = 1000;
  std::vector<double> e(n), ref(n), real(n), tiny(n), worse(n);
  for (std::size_t k = 0; k < n; ++k) {
    e[k] = noise(rng);
    const double shape = std::sin(static_cast<double>(k) / 80.0);
    ref[k] = e[k] + 0.4 * shape;                                      // a 0.4 K systematic error
    real[k] = e[k];                                                   // removes it
    tiny[k] = ref[k] + 0.05 * std::cos(static_cast<double>(k) / 7.0); // unrelated to the error
    worse[k] = e[k] + 0.5 * shape;
  }
  // Removing a 0.4 K error over 1000 points: far beyond chance; z = sum(d^2)/(2 sigma |d|) =
  // |d| / (2 sigma) plus the noise's cross term, |d| = 0.4 sqrt(n / 2) = 8.9, so z = 14.9 +- 1.
  const double z = holdout_gain_z(ref, real, 0.3);
  CHECK(z > 12.0);
  CHECK(z < 18.0);
  // A change unrelated to the error is within what noise gives; a larger error is negative.
  CHECK(holdout_gain_z(ref, tiny, 0.3) < significant_gain_z);
  CHECK(holdout_gain_z(ref, worse, 0.3) < 0.0);
  // Nothing to compare: identical fits, different lengths, no noise estimate.
  CHECK(holdout_gain_z(ref, ref, 0.3) == 0.0);
  CHECK(holdout_gain_z(ref, std::vector<double>(n - 1, 0.0), 0.3) == 0.0);
  CHECK(holdout_gain_z(ref, real, 0.0) == 0.0);
}

TEST_CASE("diagnosis report: an ambiguity set is written as the finding's candidates") {
  DiagnosisReport r;
  r.model = "m.tnet";
  r.cases = {"run"};
  r.validation = "held_back_time";
  r.folds = 1;
  Finding f;
  f.rank = 1;
  f.candidate.kind = "missing_source";
  f.candidate.nodes = {"a"};
  f.candidate.names = {"P"};
  f.values = {2.0};
  f.rmse_before = 1.0, f.rmse_after = 0.31, f.validation_rmse_after = 0.33, f.holdout_z = 40.0;
  Rival rv;
  rv.candidate.kind = "sensor_offset";
  rv.candidate.nodes = {"a"};
  rv.candidate.names = {"offset"};
  rv.values = {0.8};
  rv.rmse_after = 0.32, rv.validation_rmse_after = 0.335, rv.z = 1.2;
  f.rivals.push_back(rv);
  f.separate_by = "a second sensor beside a";
  r.findings.push_back(f);
  const nlohmann::json j = diagnosis_json(r);
  const auto& c = j["findings"][0]["candidates"];
  REQUIRE(c.size() == 2);
  CHECK(c[0]["kind"] == "missing_source"); // the finding itself first
  CHECK(c[0]["z"] == 0.0);
  CHECK(c[1]["kind"] == "sensor_offset");
  CHECK(c[1]["values"]["offset"] == 0.8);
  CHECK(c[1]["rmse"] == 0.32);
  CHECK(c[1]["validation_rmse"] == 0.335);
  CHECK(c[1]["z"] == 1.2);
  CHECK(j["findings"][0]["separate_by"] == "a second sensor beside a");
  CHECK(j["findings"][0]["holdout_z"] == 40.0);
  const std::string text = diagnosis_text(r);
  CHECK(text.find("fits as well") != std::string::npos);
  CHECK(text.find("sensor_offset [a]: RMSE 0.32 K, held-out 0.335 K") != std::string::npos);
  CHECK(text.find("to separate them: a second sensor beside a") != std::string::npos);
  // Without rivals neither field is written (the finding alone is not an ambiguity set).
  r.findings[0].rivals.clear();
  CHECK_FALSE(diagnosis_json(r)["findings"][0].contains("candidates"));
}

TEST_CASE("diagnosis statistics: residuals kept in single precision test as in double") {
  // The diagnosis keeps every candidate's residuals as floats (StoredResiduals): each test gives
  // what the doubles give, to the floats' rounding.
  std::mt19937_64 rng(17);
  std::normal_distribution<double> noise(0.0, 0.2);
  const std::size_t n = 3000;
  std::vector<double> ref(n), cand(n);
  double x = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    x = 0.9 * x + noise(rng);
    ref[k] = x + 0.3 * std::sin(static_cast<double>(k) / 60.0);
    cand[k] = x;
  }
  const StoredResiduals fref(ref.begin(), ref.end()), fcand(cand.begin(), cand.end());
  const std::vector<std::size_t> segments{1000, 2000};
  const auto rho = positive_autocorrelation(cand, segments);
  const auto frho = positive_autocorrelation(fcand, segments);
  REQUIRE(rho.size() == frho.size());
  REQUIRE_FALSE(rho.empty());
  for (std::size_t k = 0; k < rho.size(); ++k)
    CHECK(frho[k] == doctest::Approx(rho[k]).epsilon(1e-5));
  const double z = holdout_gain_z(ref, cand, rho, 0.2, segments);
  CHECK(z > 3.0);
  CHECK(holdout_gain_z(fref, fcand, frho, 0.2, segments) == doctest::Approx(z).epsilon(1e-5));
  CHECK(worst_block_gain(fref, fcand, segments) ==
        doctest::Approx(worst_block_gain(ref, cand, segments)).epsilon(1e-5));
  const std::vector<std::vector<double>> r2{ref}, c2{cand};
  const std::vector<StoredResiduals> fr2{fref}, fc2{fcand};
  CHECK(largest_window_gain(fr2, fc2) ==
        doctest::Approx(largest_window_gain(r2, c2)).epsilon(1e-5));
  CHECK(sum_of_squares(fref) == doctest::Approx(sum_of_squares(ref)).epsilon(1e-6));
}
