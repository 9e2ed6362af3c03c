#pragma once
/// How the equations C dT/dt = F(t, T) of a ThermalSystem move along parameters: what forward
/// sensitivities (CVODES) integrate beside the state.

#include <vector>

namespace thermnet {

/// The derivatives of a system's heat balance, capacities and initial state with respect to
/// parameters p_j (each in whatever unit the caller chose).
class ParameterDerivatives {
public:
  virtual ~ParameterDerivatives() = default;
  /// Number of parameters.
  virtual int count() const = 0;
  /// A typical size of parameter j (sensitivities times it are compared with the tolerances).
  virtual double scale(int j) const = 0;
  /// Writes dF/dp_j at (t, T) into dF (one per unknown), W per unit of p_j.
  virtual void heat_balance(int j, double t, const double* T, double* dF) = 0;
  /// dC/dp_j per unknown, J/K per unit of p_j (empty: the capacities do not depend on p_j).
  virtual const std::vector<double>& capacities(int j) const = 0;
  /// dT(t0)/dp_j per unknown: the derivative of the initial state.
  virtual const std::vector<double>& initial_state(int j) const = 0;
};

} // namespace thermnet
