// The bounded quasi-Newton minimiser (the likelihood's): minima inside the box and on a bound,
// reached to the accuracy its stops promise although its gradients are forward differences while
// far from the minimum; the same result whatever the number of threads.

#include "kernel/calibration/quasi_newton.hpp"

#include <doctest/doctest.h>

#include <atomic>
#include <cmath>

namespace {

using thermnet::BoundedParam;
using thermnet::ParamScale;

// Rosenbrock's valley, scaled to a likelihood's size (a minimum of -3000 at (1, 1)).
double rosenbrock(const std::vector<double>& x) {
  const double a = 1.0 - x[0], b = x[1] - x[0] * x[0];
  return -3000.0 + 100.0 * (a * a + 100.0 * b * b);
}

} // namespace

TEST_CASE("quasi-Newton: a curved valley's minimum inside the box") {
  const std::vector<BoundedParam> box = {{-2.0, 3.0, ParamScale::linear},
                                         {-1.0, 4.0, ParamScale::linear}};
  std::atomic<std::size_t> calls{0};
  const thermnet::ScalarObjective f = [&](const std::vector<double>& x) {
    ++calls;
    return rosenbrock(x);
  };
  const auto r = thermnet::minimise_bounded(f, box, {-1.2, 2.5});
  REQUIRE(r.ok);
  CHECK(r.converged);
  CHECK(std::abs(r.x[0] - 1.0) < 1e-3);
  CHECK(std::abs(r.x[1] - 1.0) < 2e-3);
  CHECK(r.f < -3000.0 + 1e-3);
  CHECK(r.evaluations == calls.load());
}

TEST_CASE("quasi-Newton: a minimum on a bound, on a log scale") {
  // f = (ln x - ln 50)^2 + (y - 7)^2 in x in [1, 20] (log), y in [0, 10]: x = 20 on its bound.
  const std::vector<BoundedParam> box = {{1.0, 20.0, ParamScale::log},
                                         {0.0, 10.0, ParamScale::linear}};
  const thermnet::ScalarObjective f = [](const std::vector<double>& x) {
    const double a = std::log(x[0] / 50.0), b = x[1] - 7.0;
    return a * a + b * b;
  };
  const auto r = thermnet::minimise_bounded(f, box, {2.0, 1.0});
  REQUIRE(r.ok);
  CHECK(r.x[0] > 19.9);
  CHECK(r.x[0] <= 20.0);
  CHECK(std::abs(r.x[1] - 7.0) < 1e-3);
}

TEST_CASE("quasi-Newton: the same result with one thread and with four") {
  const std::vector<BoundedParam> box = {{-2.0, 3.0, ParamScale::linear},
                                         {-1.0, 4.0, ParamScale::linear}};
  thermnet::QuasiNewtonOptions one, four;
  one.threads = 1;
  four.threads = 4;
  const auto a = thermnet::minimise_bounded(rosenbrock, box, {-1.2, 2.5}, one);
  const auto b = thermnet::minimise_bounded(rosenbrock, box, {-1.2, 2.5}, four);
  CHECK(a.x == b.x);
  CHECK(a.f == b.f);
  CHECK(a.evaluations == b.evaluations);
}
