#pragma once
/// What the CVODE and IDA steppers share: state and output vectors, event flags, the counters
/// accumulated over restarts, dense output, the step's outcome and the failure report.

#include "kernel/core/linear_solver_choice.hpp"
#include "kernel/core/transient_stepper.hpp"

#include <nvector/nvector_serial.h>

#include <string>
#include <vector>

namespace thermnet::detail {

/// The functions and flags of one SUNDIALS integrator that the shared code calls: CVODE and IDA
/// name them differently but give them the same shapes.
struct IntegratorApi {
  sundials::Api api;                        ///< for checked calls and flag names
  const char* name;                         ///< SolverStats::integrator ("cvode-bdf", "ida")
  int root_return;                          ///< a step's flag for "an event function crossed zero"
  int tstop_return;                         ///< a step's flag for "the stop time was reached"
  int too_much_work;                        ///< the flag of "max_steps reached"
  int repeated_rhs;                         ///< the flag of repeated heat balance failures
  int success;                              ///< the flag of a successful getter
  int (*num_steps)(void*, long*);           ///< GetNumSteps
  int (*num_lin_solv_setups)(void*, long*); ///< GetNumLinSolvSetups
  int (*num_err_test_fails)(void*, long*);  ///< GetNumErrTestFails
  int (*nonlin_solv_stats)(void*, long*, long*); ///< GetNonlinSolvStats
  int (*num_lin_iters)(void*, long*);            ///< GetNumLinIters
  int (*current_time)(void*, sunrealtype*);      ///< GetCurrentTime
  int (*err_weights)(void*, N_Vector);           ///< GetErrWeights
  int (*est_local_errors)(void*, N_Vector);      ///< GetEstLocalErrors
  int (*dky)(void*, sunrealtype, int, N_Vector); ///< GetDky (dense output)
  const char* dky_name;                          ///< its name in messages
  int (*root_info)(void*, int*);                 ///< GetRootInfo
  const char* root_info_name;                    ///< its name in messages
};

/// A TransientStepper over one SUNDIALS integrator; the derived class creates the integrator (its
/// memory, initial conditions, linear solver, root functions) and takes the steps.
class SundialsStepper : public TransientStepper {
public:
  void interpolate(double t, double* out) override;
  double* state() override { return NV_DATA_S(y_.get()); }
  const int* roots() override { return roots_.data(); }
  double current_time() override;
  long steps() override;
  void collect(SolverStats& stats) override;
  sundials::Checker& checker() override { return chk_; }
  int too_much_work_flag() const override { return api_.too_much_work; }
  int repeated_rhs_flag() const override { return api_.repeated_rhs; }
  std::string flag_name(int flag) const override { return sundials::flag_name(api_.api, flag); }

protected:
  /// Binds the evaluator and the checker (`module`: "CVODE" or "IDA"); creates nothing that can
  /// fail, so that the failure report always reaches the derived class.
  SundialsStepper(const IntegratorApi& api, const char* module, SystemEvaluator& ev,
                  LinearSolverKind kind);

  /// The integrator's memory (owned by the derived class; null until created).
  virtual void* memory() const = 0;
  /// Before the first step: adds what may explain a failure of the setup (default: nothing).
  virtual void explain_start_failure(sundials::FailureReport& d) const;

  /// Creates the state vector (holding T0) and the output vector, with the fast vector kernels.
  void create_state(const double* T0);
  /// Adds the counters of the current segment (a re-initialisation resets the integrator's own).
  void accumulate();
  /// What a step's return flag means; fetches the event flags when a root was found.
  StepResult outcome(int flag);

  SystemEvaluator& ev_;    ///< the system's evaluator (the integrator's user data)
  LinearSolverKind kind_;  ///< the linear solver in use
  int n_;                  ///< unknowns
  sundials::Checker chk_;  ///< checks every SUNDIALS call
  sundials::Context ctx_;  ///< the SUNDIALS context, outliving every object below
  sundials::NVector y_;    ///< the state
  sundials::NVector out_;  ///< wraps the caller's buffer for dense output
  LinearSystem ls_;        ///< matrix and linear solver
  std::vector<int> roots_; ///< event flags after a root was found
  bool started_ = false;   ///< a step was attempted

private:
  /// Time reached, a non-finite heat balance, and the unknowns with the largest weighted local
  /// error estimates (or, before the first step, what explain_start_failure() finds).
  sundials::FailureReport failure_report();

  const IntegratorApi& api_;
  SolverStats acc_; ///< counters of the finished segments
};

} // namespace thermnet::detail
