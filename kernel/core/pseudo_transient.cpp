// pseudo_transient(): relaxes a guess toward the steady state by CVODE in pseudo-time, so that
// Newton starts close enough (pseudo-transient continuation).

#include "kernel/core/pseudo_transient.hpp"

#include "kernel/core/integrator.hpp"

#include <algorithm>
#include <cmath>

namespace thermnet::detail {

namespace {

/// Pseudo-time long enough for every mode to settle: the fastest relax in about a second, and
/// BDF's steps grow with the slowest ones.
constexpr double kPseudoTimeEnd = 1e9;
/// Internal steps allowed for the walk (it is a start for Newton, not the answer).
constexpr long kMaxPseudoSteps = 20000;

/// The system with its inputs held at one time, no events, and capacities of its own choosing.
class HeldInputs final : public ForwardingSystem {
public:
  HeldInputs(ThermalSystem& inner, double t, std::vector<double> capacities)
      : ForwardingSystem(inner), t_(t), capacities_(std::move(capacities)) {}
  const std::vector<double>& capacities() const override { return capacities_; }
  void heat_balance(double, const double* T, double* F) override {
    ForwardingSystem::heat_balance(t_, T, F);
  }
  void jacobian(double, const double* T, double* values) override {
    ForwardingSystem::jacobian(t_, T, values);
  }
  int event_count() const override { return 0; } // thermostats keep the steady solve's states
  void init_events(double, const double*) override {}
  std::vector<double> breakpoints(double, double) const override { return {}; }

private:
  double t_;
  std::vector<double> capacities_;
};

/// |dF_i/dT_i| * 1 s at T, floored so that an unknown without conductance still has a capacity.
std::vector<double> unit_time_capacities(ThermalSystem& sys, double t,
                                         const std::vector<double>& T) {
  const SparsityPattern& p = sys.jacobian_pattern();
  std::vector<double> values(static_cast<std::size_t>(p.nnz()));
  sys.jacobian(t, T.data(), values.data());
  std::vector<double> c(static_cast<std::size_t>(p.n), 0.0);
  double largest = 0.0;
  for (int i = 0; i < p.n; ++i)
    for (int k = p.row_ptr[i]; k < p.row_ptr[i + 1]; ++k)
      if (p.col_idx[k] == i && std::isfinite(values[k])) {
        c[i] = std::abs(values[k]);
        largest = std::max(largest, c[i]);
      }
  const double floor = largest > 0.0 ? 1e-9 * largest : 1.0;
  for (double& x : c)
    x = std::max(x, floor);
  return c;
}

} // namespace

bool pseudo_transient(ThermalSystem& sys, std::vector<double>& T, double t,
                      const SolverOptions& opt) {
  std::vector<double> walked = T;
  try {
    HeldInputs held(sys, t, unit_time_capacities(sys, t, T));
    SolverOptions o = opt;
    o.max_step = 0.0;
    o.max_steps = kMaxPseudoSteps;
    integrate(held, walked, 0.0, kPseudoTimeEnd, {}, nullptr, o);
  } catch (const SolverError&) {
    return false;
  }
  if (!std::all_of(walked.begin(), walked.end(), [](double x) { return std::isfinite(x); }))
    return false;
  T = std::move(walked);
  return true;
}

} // namespace thermnet::detail
