#pragma once
/// Evaluation of a ThermalSystem on behalf of SUNDIALS callbacks: time clamped inside the current
/// segment, non-finite detection, user exceptions kept for rethrowing, Jacobian storage, counters.

#include "kernel/core/sparse_jacobian.hpp"
#include "kernel/core/thermal_system.hpp"

#include <cstddef>
#include <exception>
#include <string>
#include <vector>

namespace thermnet::detail {

struct SensitivityContext;

/// The most recent non-finite value seen in the heat balance or the Jacobian.
struct NonFinite {
  bool seen = false;     ///< whether anything non-finite was seen since the last clear()
  bool jacobian = false; ///< in dF/dT rather than F
  double time = 0.0;     ///< time of the evaluation, s
  int index = -1;        ///< unknown (row) affected
  double value = 0.0;    ///< the offending value
};

/// Wraps a ThermalSystem for the solvers. Callback-side methods never allocate.
class SystemEvaluator {
public:
  /// Validates sizes and pattern; precomputes 1/C (0 for algebraic nodes).
  explicit SystemEvaluator(ThermalSystem& sys);

  /// The wrapped system.
  ThermalSystem& system() { return *sys_; }
  /// Number of unknowns.
  int size() const { return n_; }
  /// Heat capacities, J/K.
  const std::vector<double>& capacities() const { return caps_; }
  /// 1/C for capacitive nodes, 0 for algebraic ones.
  const std::vector<double>& inverse_capacities() const { return inv_caps_; }
  /// Whether some node has zero capacity.
  bool has_algebraic() const { return has_algebraic_; }
  /// The Jacobian storage.
  SparseJacobian& jacobian_storage() { return jac_; }

  /// Restricts evaluation times to the open interval (a, b): the inputs of a segment between
  /// breakpoints are continuous there, so its end points see the segment's own inputs.
  void set_window(double a, double b);
  /// Time actually passed to the system for a solver time t.
  double clamp(double t) const { return t < lo_ ? lo_ : (t > hi_ ? hi_ : t); }

  /// F(t, T) into F; 0 on success, 1 (recoverable) if a value is not finite, -1 if it threw.
  int heat_balance(double t, const double* T, double* F);
  /// dF/dT(t, T) into the Jacobian storage; 0, 1 (non-finite) or -1 (threw).
  int jacobian(double t, const double* T);
  /// Event functions g(t, T); 0 or -1 (threw).
  int events(double t, const double* T, double* g);

  /// The last non-finite value seen since clear_nonfinite().
  const NonFinite& nonfinite() const { return nonfinite_; }
  /// Forgets non-finite values seen so far.
  void clear_nonfinite() { nonfinite_.seen = false; }
  /// Name of unknown i (ThermalSystem::unknown_name).
  std::string name(int i) const;
  /// A sentence fragment describing the last non-finite value, or "" if none.
  std::string describe_nonfinite() const;
  /// Names of up to `count` unknowns whose row of the last evaluated dF/dT has a zero diagonal
  /// (a node coupled to nothing makes the Newton matrix singular); only algebraic nodes if asked.
  std::vector<std::string> zero_diagonal_unknowns(bool algebraic_only, std::size_t count = 3) const;
  /// Names of up to `count` unknowns with the largest `score` (NaN counts as largest; zeros
  /// skipped).
  std::vector<std::string> worst_unknowns(const double* score, std::size_t count = 3) const;

  /// An exception thrown by the system inside a callback, rethrown after SUNDIALS returns.
  std::exception_ptr pending;
  /// Heat balance evaluations made by the solvers.
  long rhs_evals = 0;
  /// Jacobian evaluations made by the solvers.
  long jac_evals = 0;
  /// What the sensitivity right-hand side needs (CVODES forward sensitivities), or null.
  SensitivityContext* sensitivities = nullptr;

private:
  void record(bool jacobian, double t, int index, double value);

  ThermalSystem* sys_;
  int n_;
  std::vector<double> caps_;
  std::vector<double> inv_caps_;
  bool has_algebraic_ = false;
  SparseJacobian jac_;
  double lo_;
  double hi_;
  NonFinite nonfinite_;
};

} // namespace thermnet::detail
