// pseudo_transient(): relaxes a guess toward the steady state by CVODE in pseudo-time, so that
// Newton starts close enough (pseudo-transient continuation).

#include "kernel/core/pseudo_transient.hpp"

#include "kernel/core/integrator.hpp"
#include "kernel/core/system_evaluator.hpp"

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

/// |dF_i/dT_i| * 1 s at T, floored so that an unknown without conductance still has a capacity;
/// empty when the Jacobian cannot be evaluated there.
std::vector<double> unit_time_capacities(SystemEvaluator& ev, double t,
                                         const std::vector<double>& T) {
  if (ev.jacobian(t, T.data()) != 0) return {};
  std::vector<double> c(static_cast<std::size_t>(ev.size()));
  for (int i = 0; i < ev.size(); ++i)
    c[static_cast<std::size_t>(i)] = std::abs(ev.jacobian_storage().diagonal(i));
  const double largest = *std::max_element(c.begin(), c.end());
  const double floor = largest > 0.0 ? 1e-9 * largest : 1.0;
  for (double& x : c)
    x = std::max(x, floor);
  return c;
}

} // namespace

bool pseudo_transient(SystemEvaluator& ev, std::vector<double>& T, double t,
                      const SolverOptions& opt) {
  std::vector<double> capacities = unit_time_capacities(ev, t, T);
  if (capacities.empty()) return false;
  std::vector<double> walked = T;
  try {
    HeldInputs held(ev.system(), t, std::move(capacities));
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
