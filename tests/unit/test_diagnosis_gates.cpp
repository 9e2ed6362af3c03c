// What the diagnosis leaves out without changing its answers: counterparts on unmeasured nodes
// beside a proxy that gains nothing or less than the best of its kind (beside_gaining), a screen
// basis asked only where it acts (Evidence::regress with a support), and the lagged sums of the
// held-out test (against the sums written out point by point).

#include "kernel/diagnosis/selection.hpp"
#include "kernel/diagnosis/statistics.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

namespace thermnet::detail {
namespace {

/// An entry of `kind` on `nodes` standing beside the proxy site `proxy` (empty: none).
Entry counterpart(std::vector<std::string> nodes, std::string proxy,
                  std::string kind = "missing_link") {
  Entry e;
  e.c.kind = std::move(kind);
  e.c.nodes = std::move(nodes);
  e.proxy = std::move(proxy);
  return e;
}

/// A refit with ΔBIC `bic` and RMSE `rmse` (failed: no values).
Evaluated refit(double bic, bool failed = false, double rmse = 0.5) {
  Evaluated e;
  if (!failed) e.f.values = {1.0};
  e.f.delta_bic = bic;
  e.f.rmse_after = rmse;
  return e;
}

/// holdout_gain_z's formula written out point by point, one run.
double gain_z_direct(const std::vector<double>& ref, const std::vector<double>& cand,
                     const std::vector<double>& rho, double noise) {
  double gain = 0.0, cand2 = 0.0, dd = 0.0, cross = 0.0;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    const double d = ref[i] - cand[i];
    dd += d * d;
    for (std::size_t lag = 1; lag <= rho.size() && i + lag < ref.size(); ++lag)
      cross += rho[lag - 1] * d * (ref[i + lag] - cand[i + lag]);
    gain += ref[i] * ref[i] - cand[i] * cand[i];
    cand2 += cand[i] * cand[i];
  }
  const double s2 = std::max(noise * noise, cand2 / static_cast<double>(cand.size()));
  return gain / (2.0 * std::sqrt(s2 * std::max(dd, dd + 2.0 * cross)));
}

} // namespace

TEST_CASE("diagnosis gates: counterparts only beside a proxy that gains, fails or is unknown") {
  // entries 0-2 are proxies p1, p2, p3; 3-6 counterparts beside p1, p2, p3 and p4 (not refitted).
  const std::string p1 = "missing_link|a,b|", p2 = "missing_link|c,d|", p3 = "missing_link|e,f|",
                    p4 = "missing_link|g,h|";
  const std::vector<Entry> entries = {counterpart({"a", "b"}, ""),  counterpart({"c", "d"}, ""),
                                      counterpart({"e", "f"}, ""),  counterpart({"a", "u1"}, p1),
                                      counterpart({"c", "u2"}, p2), counterpart({"e", "u3"}, p3),
                                      counterpart({"g", "u4"}, p4)};
  REQUIRE(site(entries[0].c) == p1); // the proxies' sites as the shortlist writes them
  const std::vector<std::size_t> refitted = {0, 1, 2}, beside = {3, 4, 5, 6};
  std::vector<Evaluated> res(entries.size());
  res[0] = refit(-25.0);     // gains against the declared model
  res[1] = refit(-4.0);      // does not
  res[2] = refit(0.0, true); // failed

  SUBCASE("against the model the findings extend (reference ΔBIC 0)") {
    // p1 gains, p3 failed, p4 was not refitted: their counterparts; p2's is left out.
    CHECK(beside_gaining(entries, beside, res, refitted, 0.0, 6) ==
          std::vector<std::size_t>{3, 5, 6});
  }
  SUBCASE("against a recalibration that already gains as much") {
    // ΔBICs are against the declared model: p1's -25 is only -5 against a recalibration at -20.
    CHECK(beside_gaining(entries, beside, res, refitted, -20.0, 6) ==
          std::vector<std::size_t>{5, 6});
  }
}

TEST_CASE("diagnosis gates: counterparts only beside the best gaining proxies of their kind") {
  // Proxies 0-3 all gain: links p1 (RMSE 0.5, both mechanisms), p2 (0.4), p3 (0.6), and a hidden
  // mass h1 (0.7), ranked apart from the links; 4-8 are counterparts beside p1, p2, p3, h1 and a
  // proxy p4 not refitted.
  const std::string p1 = "missing_link|a,b|", p2 = "missing_link|c,d|", p3 = "missing_link|e,f|",
                    p4 = "missing_link|g,h|", h1 = "hidden_mass|a|";
  const std::vector<Entry> entries = {counterpart({"a", "b"}, ""),
                                      counterpart({"c", "d"}, ""),
                                      counterpart({"e", "f"}, ""),
                                      counterpart({"a"}, "", "hidden_mass"),
                                      counterpart({"a", "b"}, ""),
                                      counterpart({"a", "u1"}, p1),
                                      counterpart({"c", "u2"}, p2),
                                      counterpart({"e", "u3"}, p3),
                                      counterpart({"u4"}, h1, "hidden_mass"),
                                      counterpart({"g", "u5"}, p4)};
  REQUIRE(site(entries[3].c) == h1);
  const std::vector<std::size_t> refitted = {0, 1, 2, 3, 4}, beside = {5, 6, 7, 8, 9};
  std::vector<Evaluated> res(entries.size());
  res[0] = refit(-25.0, false, 0.5);
  res[1] = refit(-40.0, false, 0.4);
  res[2] = refit(-30.0, false, 0.6);
  res[3] = refit(-15.0, false, 0.7);
  res[4] = refit(-24.0, false, 0.55); // p1's other mechanism: the same site, counted once
  // The best two links (p2, p1) and the best hidden mass keep theirs; p3's is left out; p4's
  // proxy was not refitted.
  CHECK(beside_gaining(entries, beside, res, refitted, 0.0, 2) ==
        std::vector<std::size_t>{5, 6, 8, 9});
  CHECK(beside_gaining(entries, beside, res, refitted, 0.0, 3) ==
        std::vector<std::size_t>{5, 6, 7, 8, 9});
  // Only the gaining proxies are ranked: against a reference at -28, p2 (and h1's none).
  CHECK(beside_gaining(entries, beside, res, refitted, -28.0, 2) == std::vector<std::size_t>{6, 9});
}

TEST_CASE("diagnosis gates: a screen basis asked only on its support fits the same") {
  Evidence ev;
  ev.cases.emplace_back();
  CaseEvidence& ce = ev.cases.front();
  for (const char* name : {"n0", "n1", "n2", "n3"}) {
    lang::NodeSpec n;
    n.name = name;
    n.C = 10.0 + static_cast<double>(ce.spec.nodes.size());
    ce.spec.nodes.push_back(n);
  }
  ce.rows = {0, 1, 3};
  const double nan = std::nan("");
  for (int k = 0; k < 50; ++k)
    ce.q.push_back(std::vector<double>{std::sin(0.1 * k) + 0.3, 0.5 * std::cos(0.2 * k), nan,
                                       k % 7 == 0 ? nan : 0.01 * k});
  ev.sum_screen();
  std::size_t asked = 0;
  const auto basis = [&](std::size_t, int node, std::size_t k) {
    ++asked;
    if (node == 1) return std::cos(0.2 * static_cast<double>(k));
    if (node == 3) return 0.02 * static_cast<double>(k) - 0.4;
    return 0.0;
  };
  const ScreenFit everywhere = ev.regress(basis);
  const std::size_t asked_everywhere = asked;
  asked = 0;
  const ScreenFit on_support = ev.regress(basis, {1, 3});
  // the same terms in the same order: the same numbers to the bit
  CHECK(on_support.coefficient == everywhere.coefficient);
  CHECK(on_support.reduction == everywhere.reduction);
  CHECK(on_support.correlation == everywhere.correlation);
  CHECK(everywhere.reduction > 0.0);
  CHECK(asked_everywhere == 50 + 50 + 42);
  CHECK(asked == 50 + 42); // node 0 is not asked; node 3's missing samples neither
  // the weighted least-squares fit and correlation written out over every row (q in K/s)
  double qb = 0.0, bb = 0.0, qq = 0.0;
  for (int node : ce.rows)
    for (std::size_t k = 0; k < ce.q.size(); ++k) {
      const double C = ce.spec.nodes[static_cast<std::size_t>(node)].C;
      const double q = ce.q[k][static_cast<std::size_t>(node)];
      if (std::isnan(q)) continue;
      const double b = basis(0, node, k);
      qb += q * b / (C * C), bb += b * b / (C * C), qq += q * q / (C * C);
    }
  CHECK(everywhere.coefficient == doctest::Approx(qb / bb).epsilon(1e-12));
  CHECK(everywhere.reduction == doctest::Approx(qb * qb / bb).epsilon(1e-12));
  CHECK(everywhere.correlation == doctest::Approx(qb / std::sqrt(bb * qq)).epsilon(1e-12));
  CHECK(std::abs(everywhere.correlation) < 1.0);
}

TEST_CASE("diagnosis gates: the held-out test's lagged sums match the point-by-point formula") {
  // A slowly varying difference over correlated residuals: many positive lags.
  std::vector<double> ref, cand;
  for (int i = 0; i < 600; ++i) {
    const double t = 0.05 * i;
    cand.push_back(0.3 * std::sin(t) + 0.1 * std::sin(7.3 * t));
    ref.push_back(cand.back() + 0.2 * std::cos(0.3 * t));
  }
  const std::vector<double> rho = positive_autocorrelation(cand);
  REQUIRE(rho.size() > 10);
  // rho's lag 1 written out: sum of centred products over the sum of squares
  double mean = 0.0;
  for (double x : cand)
    mean += x;
  mean /= static_cast<double>(cand.size());
  double s0 = 0.0, s1 = 0.0;
  for (std::size_t k = 0; k < cand.size(); ++k) {
    s0 += (cand[k] - mean) * (cand[k] - mean);
    if (k + 1 < cand.size()) s1 += (cand[k] - mean) * (cand[k + 1] - mean);
  }
  CHECK(rho.front() == doctest::Approx(s1 / s0).epsilon(1e-12));
  const double z = holdout_gain_z(ref, cand, rho, 0.1, {});
  CHECK(z > 0.0);
  CHECK(z == doctest::Approx(gain_z_direct(ref, cand, rho, 0.1)).epsilon(1e-12));
}

} // namespace thermnet::detail
