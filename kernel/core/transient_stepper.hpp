#pragma once
/// The step-by-step interface the transient driver (integrate) uses over CVODE and IDA.

#include "kernel/core/integrator.hpp"
#include "kernel/core/parameter_derivatives.hpp"
#include "kernel/core/sundials_check.hpp"
#include "kernel/core/system_evaluator.hpp"

#include <memory>

namespace thermnet::detail {

/// What one call of TransientStepper::step() ended with.
enum class StepResult {
  advanced,     ///< an internal step was taken (or the rest of a step after a root was returned)
  stop_reached, ///< the stop time was reached exactly
  root_found    ///< an event function crossed zero; the state is at the root time
};

/// One integrator (CVODE or IDA) advanced one internal step at a time towards a stop time.
class TransientStepper {
public:
  virtual ~TransientStepper() = default;
  /// Restarts at time t from the current state(), integrating towards the stop time `stop`.
  virtual void restart(double t, double stop) = 0;
  /// Takes one internal step (CV_ONE_STEP / IDA_ONE_STEP) without passing `stop`; sets t.
  virtual StepResult step(double stop, double& t) = 0;
  /// Writes the dense-output state at time t (within the last step) into out.
  virtual void interpolate(double t, double* out) = 0;
  /// Writes the dense-output sensitivities at time t into out[j] (one per parameter); nothing
  /// when the stepper integrates none.
  virtual void interpolate_sensitivities(double /*t*/, std::vector<std::vector<double>>& /*out*/) {}
  /// dT/dt at the state set up by the last restart() (F/C, or IDA's consistent T').
  virtual void derivative(double* out) = 0;
  /// The state at the time last returned by step() (or set up by restart()), one per unknown.
  virtual double* state() = 0;
  /// Event flags after root_found: +1 rising, -1 falling, 0 not fired (one per event function).
  virtual const int* roots() = 0;
  /// The time of the current state (the last step's end, or the restart time).
  virtual double current_time() = 0;
  /// Internal steps taken over the whole run (all segments).
  virtual long steps() = 0;
  /// Adds the counters of the whole run to stats (integrator, linear solver, steps, ...).
  virtual void collect(SolverStats& stats) = 0;
  /// The checker of this integrator's calls (for failures detected by the driver).
  virtual sundials::Checker& checker() = 0;
  /// The flag that reports "too much work" for this integrator (for max_steps).
  virtual int too_much_work_flag() const = 0;
  /// The flag reporting repeated heat balance failures for this integrator.
  virtual int repeated_rhs_flag() const = 0;
  /// Name of a flag of this integrator.
  virtual std::string flag_name(int flag) const = 0;
};

/// Forward sensitivities for a CVODE stepper: the parameters and dT(t0)/dp_j.
struct SensitivityStart {
  ParameterDerivatives* derivatives = nullptr;          ///< the parameters (null: none)
  const std::vector<std::vector<double>>* S0 = nullptr; ///< S0[j]: dT(t0)/dp_j per unknown
};

/// CVODE BDF on dT/dt = F/C (all capacities > 0), started at t0 from T0 with stop time `stop`;
/// with `sens`, CVODES integrates the forward sensitivities too (staggered corrector, the
/// steps controlled by the state's error only).
std::unique_ptr<TransientStepper> make_cvode_stepper(SystemEvaluator& ev, LinearSolverKind kind,
                                                     const SolverOptions& opt, double t0,
                                                     const double* T0, double stop,
                                                     SensitivityStart sens = {});

/// IDA on C T' - F = 0 with consistent initial conditions (IDACalcIC), started at t0 from T0.
std::unique_ptr<TransientStepper> make_ida_stepper(SystemEvaluator& ev, LinearSolverKind kind,
                                                   const SolverOptions& opt, double t0,
                                                   const double* T0, double stop);

} // namespace thermnet::detail
