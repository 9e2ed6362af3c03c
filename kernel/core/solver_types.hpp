#pragma once
/// The vocabulary of every solve: linear solver choice, tolerances, counters and the failure type.

#include <stdexcept>
#include <string>
#include <vector>

namespace thermnet {

/// Which linear solver the Newton iterations use.
enum class LinearSolverKind {
  automatic, ///< dense for small networks, KLU for medium ones, preconditioned Krylov for large
             ///< ones
  dense,     ///< dense LU
  klu,       ///< sparse direct LU (SuiteSparse KLU) on the network's pattern
  krylov ///< preconditioned GMRES (SPGMR) with Jacobian-vector products from the analytic Jacobian
};

/// Tolerances and choices for a solve.
struct SolverOptions {
  double rtol = 1e-6;                                           ///< relative tolerance
  double atol = 1e-6;                                           ///< absolute tolerance in K
  LinearSolverKind linear_solver = LinearSolverKind::automatic; ///< linear solver
  int dense_threshold = 200; ///< automatic: dense at or below this many unknowns
  /// automatic: KLU up to this many unknowns, Krylov above (KLU fill-in grows fast on 2-D meshes).
  int krylov_threshold = 2000;
  double max_step = 0.0;    ///< largest step in s (0: unlimited)
  long max_steps = 1000000; ///< most internal steps over the whole run
  /// Forward sensitivities: their corrector stops at this relative (and, times each parameter's
  /// typical size, absolute) accuracy when it is looser than rtol/atol; their error does not
  /// control the steps, which are the state's.
  double sensitivity_tolerance = 1e-4;
  /// Solve a piecewise-affine system (ThermalSystem::piecewise_affine()) of at most this many
  /// unknowns by its exact discretisation instead of CVODE (0: never; exact_linear.hpp).
  int exact_linear_max = 0;
  /// On that path, step a reciprocal network through its eigenmodes (SymmetricModes: cheap for
  /// any interval length) rather than one matrix exponential per interval length.
  bool exact_modes = true;
};

/// Counters of a solve (printed by --stats).
struct SolverStats {
  std::string integrator;        ///< "cvode-bdf", "ida", "kinsol" or "kinsol+pseudo-transient"
  std::string linear_solver;     ///< "dense", "klu" or "spgmr"
  long steps = 0;                ///< internal steps (Newton iterations for KINSOL)
  long rhs_evals = 0;            ///< right-hand side / residual evaluations
  long jac_evals = 0;            ///< Jacobian evaluations
  long linear_setups = 0;        ///< linear solver setups (factorisations)
  long nonlinear_iters = 0;      ///< nonlinear (Newton) iterations
  long nonlinear_fails = 0;      ///< nonlinear convergence failures
  long linear_iters = 0;         ///< Krylov (GMRES) iterations (0 for direct solvers)
  long prec_setups = 0;          ///< preconditioner setups: ILU(0) factorisations (Krylov only)
  long error_test_fails = 0;     ///< local error test failures
  long events = 0;               ///< events applied (thermostat switches)
  long restarts = 0;             ///< restarts at breakpoints and events
  long sensitivities = 0;        ///< forward sensitivities integrated with the state (CVODES)
  long sens_rhs_evals = 0;       ///< their right-hand side evaluations (all sensitivities at once)
  long sens_nonlinear_iters = 0; ///< their corrector (Newton) iterations
  long sens_nonlinear_fails = 0; ///< their corrector convergence failures
};

/// A solver failure: the SUNDIALS call, its flag, the simulation time and the worst unknowns.
struct SolverError : std::runtime_error {
  /// Builds the error; `what` is a complete sentence naming time and nodes.
  SolverError(const std::string& what, std::string call_, int flag_, double time_,
              std::vector<std::string> worst_)
      : std::runtime_error(what), call(std::move(call_)), flag(flag_), time(time_),
        worst(std::move(worst_)) {}
  std::string call;               ///< the SUNDIALS function that failed
  int flag;                       ///< its return flag
  double time;                    ///< simulation time reached, s
  std::vector<std::string> worst; ///< unknowns with the largest weighted local error, worst first
};

} // namespace thermnet
