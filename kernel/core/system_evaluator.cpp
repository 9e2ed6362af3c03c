#include "kernel/core/system_evaluator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace thermnet::detail {

SystemEvaluator::SystemEvaluator(ThermalSystem& sys)
    : sys_(&sys), n_(sys.size()), caps_(sys.capacities()), jac_(sys.jacobian_pattern()),
      lo_(-std::numeric_limits<double>::infinity()), hi_(std::numeric_limits<double>::infinity()) {
  if (n_ < 0) throw std::invalid_argument("ThermalSystem::size() is negative");
  if (caps_.size() != static_cast<std::size_t>(n_))
    throw std::invalid_argument(
        fmt::format("ThermalSystem has {} unknowns but {} capacities", n_, caps_.size()));
  if (jac_.size() != n_)
    throw std::invalid_argument(fmt::format(
        "ThermalSystem has {} unknowns but a {}-row Jacobian pattern", n_, jac_.size()));
  inv_caps_.resize(caps_.size());
  for (std::size_t i = 0; i < caps_.size(); ++i) {
    const double c = caps_[i];
    if (!(c >= 0.0) || !std::isfinite(c))
      throw std::invalid_argument(
          fmt::format("the capacity of {} is {} J/K", sys.unknown_name(static_cast<int>(i)), c));
    if (c == 0.0) has_algebraic_ = true;
    inv_caps_[i] = c > 0.0 ? 1.0 / c : 0.0;
  }
}

void SystemEvaluator::set_window(double a, double b) {
  lo_ = std::nextafter(a, std::numeric_limits<double>::infinity());
  hi_ = std::nextafter(b, -std::numeric_limits<double>::infinity());
  if (lo_ > hi_) lo_ = hi_ = 0.5 * (a + b);
}

void SystemEvaluator::record(bool jacobian, double t, int index, double value) {
  nonfinite_ = NonFinite{true, jacobian, t, index, value};
}

int SystemEvaluator::heat_balance(double t, const double* T, double* F) {
  ++rhs_evals;
  const double tc = clamp(t);
  try {
    sys_->heat_balance(tc, T, F);
  } catch (...) {
    pending = std::current_exception();
    return -1;
  }
  // 0 * x is NaN exactly when x is not finite; the sum vectorises and tests all at once.
  double probe = 0.0;
  for (int i = 0; i < n_; ++i)
    probe += 0.0 * F[i];
  if (probe == 0.0) return 0;
  for (int i = 0; i < n_; ++i)
    if (!std::isfinite(F[i])) {
      record(false, tc, i, F[i]);
      break;
    }
  return 1;
}

int SystemEvaluator::jacobian(double t, const double* T) {
  ++jac_evals;
  const double tc = clamp(t);
  double* v = jac_.values();
  try {
    sys_->jacobian(tc, T, v);
  } catch (...) {
    pending = std::current_exception();
    return -1;
  }
  const int nnz = jac_.nnz();
  double probe = 0.0;
  for (int p = 0; p < nnz; ++p)
    probe += 0.0 * v[p];
  if (probe == 0.0) return 0;
  const SparsityPattern& pat = sys_->jacobian_pattern();
  for (int i = 0; i < n_; ++i)
    for (int p = pat.row_ptr[static_cast<std::size_t>(i)];
         p < pat.row_ptr[static_cast<std::size_t>(i) + 1]; ++p)
      if (!std::isfinite(v[p])) {
        record(true, tc, i, v[p]);
        return 1;
      }
  return 1;
}

int SystemEvaluator::events(double t, const double* T, double* g) {
  try {
    sys_->events(clamp(t), T, g);
  } catch (...) {
    pending = std::current_exception();
    return -1;
  }
  return 0;
}

std::string SystemEvaluator::name(int i) const {
  return sys_->unknown_name(i);
}

std::string SystemEvaluator::describe_nonfinite() const {
  if (!nonfinite_.seen) return {};
  return fmt::format("the {} was not finite ({}) at node {} at t = {:.10g} s",
                     nonfinite_.jacobian ? "Jacobian of the heat balance" : "heat balance",
                     nonfinite_.value, sys_->unknown_name(nonfinite_.index), nonfinite_.time);
}

std::vector<std::string> SystemEvaluator::zero_diagonal_unknowns(bool algebraic_only,
                                                                 std::size_t count) const {
  std::vector<std::string> names;
  for (int i = 0; i < n_ && names.size() < count; ++i)
    if (jac_.diagonal(i) == 0.0 && (!algebraic_only || caps_[static_cast<std::size_t>(i)] == 0.0))
      names.push_back(sys_->unknown_name(i));
  return names;
}

std::vector<std::string> SystemEvaluator::worst_unknowns(const double* score,
                                                         std::size_t count) const {
  std::vector<std::string> names;
  if (score == nullptr || n_ == 0) return names;
  std::vector<int> idx(static_cast<std::size_t>(n_));
  std::iota(idx.begin(), idx.end(), 0);
  const auto key = [&](int i) {
    const double s = std::abs(score[i]);
    return std::isnan(s) ? std::numeric_limits<double>::infinity() : s;
  };
  const std::size_t k = std::min(count, idx.size());
  std::partial_sort(idx.begin(), idx.begin() + static_cast<std::ptrdiff_t>(k), idx.end(),
                    [&](int a, int b) { return key(a) > key(b); });
  for (std::size_t j = 0; j < k; ++j)
    if (key(idx[j]) > 0.0) names.push_back(sys_->unknown_name(idx[j]));
  return names;
}

} // namespace thermnet::detail
