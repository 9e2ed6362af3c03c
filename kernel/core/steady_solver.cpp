// solve_steady(): F(t, T) = 0 by KINSOL's Newton method with line search and the analytic Jacobian,
// from a pseudo-transient walk when Newton cannot get there from the guess.

#include "kernel/core/integrator.hpp"

#include "kernel/core/absolute_zero.hpp"
#include "kernel/core/fast_kernels.hpp"
#include "kernel/core/linear_solver_choice.hpp"
#include "kernel/core/pseudo_transient.hpp"
#include "kernel/core/sundials_check.hpp"
#include "kernel/core/system_evaluator.hpp"

#include <kinsol/kinsol.h>
#include <kinsol/kinsol_ls.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

namespace thermnet {

namespace {

using sundials::Api;

/// Newton iterations allowed (capped by SolverOptions::max_steps).
constexpr long kMaxNewtonIterations = 500;
/// Converged when every residual, expressed as a temperature (F_i / |dF_i/dT_i|), is below this
/// fraction of atol.
constexpr double kResidualFraction = 1e-3;
/// Stops when Newton steps are below this fraction of atol (in K).
constexpr double kStepFraction = 1e-3;

struct SteadyData {
  detail::SystemEvaluator* ev;
  double t;
};

int kin_func(N_Vector u, N_Vector f, void* user_data) {
  auto* d = static_cast<SteadyData*>(user_data);
  return d->ev->heat_balance(d->t, NV_DATA_S(u), NV_DATA_S(f));
}

int kin_jac(N_Vector u, N_Vector /*fu*/, SUNMatrix J, void* user_data, N_Vector, N_Vector) {
  auto* d = static_cast<SteadyData*>(user_data);
  if (const int r = d->ev->jacobian(d->t, NV_DATA_S(u)); r != 0) return r;
  detail::SparseJacobian& jac = d->ev->jacobian_storage();
  const detail::Combination j{1.0, nullptr, 0.0, nullptr};
  if (SUNMatGetID(J) == SUNMATRIX_DENSE) {
    jac.fill_dense(J, j);
  } else {
    jac.copy_pattern(J); // KINSOL zeroes the whole sparse matrix, index arrays included
    jac.fill_sparse_values(J, j);
  }
  return 0;
}

/// The KINSOL problem of one steady state: the unknowns with their scales and constraints, and
/// the solver set up for Newton's method with line search.
class SteadyProblem {
public:
  /// Sets up F(t, T) = 0 from the guess T with the linear solver `kind` (not automatic).
  SteadyProblem(detail::SystemEvaluator& ev, double t, const std::vector<double>& T,
                LinearSolverKind kind, const SolverOptions& opt)
      : ev_(ev), t_(t), n_(ev.size()), kind_(kind), data_{&ev, t} {
    chk_.steady = true;
    chk_.pending = &ev_.pending;
    const SUNContext sc = ctx_.get();
    u_.reset(chk_.created(N_VNew_Serial(n_, sc), "N_VNew_Serial"));
    uscale_.reset(chk_.created(N_VNew_Serial(n_, sc), "N_VNew_Serial"));
    fscale_.reset(chk_.created(N_VNew_Serial(n_, sc), "N_VNew_Serial"));
    constraints_.reset(chk_.created(N_VNew_Serial(n_, sc), "N_VNew_Serial"));
    for (N_Vector v : {u_.get(), uscale_.get(), fscale_.get(), constraints_.get()})
      detail::accelerate_vector(v);
    std::copy(T.begin(), T.end(), NV_DATA_S(u_.get()));
    N_VConst(1.0, uscale_.get());
    scale_residuals();
    // Temperatures are absolute: keep the iterates above 0 K when the guess is (other unknowns,
    // such as a thermostat's sensor reading, are left unconstrained).
    const int temps = ev.system().temperature_count();
    positive_ = std::all_of(T.begin(), T.begin() + temps, [](double x) { return x > 0.0; });
    N_VConst(0.0, constraints_.get());
    if (positive_)
      std::fill(NV_DATA_S(constraints_.get()), NV_DATA_S(constraints_.get()) + temps, 2.0);
    kin_.reset(chk_.created(KINCreate(sc), "KINCreate"));
    chk_.describe_failure = [this] { return failure_report(); };
    configure(kind, opt, positive_);
  }

  /// Solves from the guess T and writes the temperatures found to T; throws SolverError when
  /// there are none or they lie below 0 K. From a guess above 0 K the iterates stay there (the
  /// physical root of T^4); if they cannot, an unconstrained search tells whether the steady
  /// state lies below 0 K (a failure naming the node) or the floor only hampered Newton.
  void solve(std::vector<double>& T, const SolverOptions& opt) {
    try {
      newton(opt);
    } catch (const SolverError&) {
      if (!positive_) throw;
      const std::exception_ptr constrained = std::current_exception();
      positive_ = false;
      std::copy(T.begin(), T.end(), NV_DATA_S(u_.get()));
      kin_.reset(chk_.created(KINCreate(ctx_.get()), "KINCreate")); // a failed KINSol is spent
      configure(kind_, opt, false);
      try {
        newton(opt);
      } catch (const SolverError&) {
        std::rethrow_exception(constrained);
      }
    }
    const double* uu = NV_DATA_S(u_.get());
    if (const int i = detail::coldest_below_absolute_zero(uu, ev_.system().temperature_count());
        i >= 0)
      detail::fail_below_absolute_zero(
          ev_, {.unknown = i, .crossing = t_, .kelvin = uu[i], .reached = t_, .steady = true},
          "KINSol");
    std::copy(uu, uu + n_, T.begin());
  }

  /// Newton iterations, Jacobian evaluations and the evaluator's call counts.
  void collect(SolverStats& stats) const {
    long nni = 0, nje = 0;
    KINGetNumNonlinSolvIters(kin_.get(), &nni);
    KINGetNumJacEvals(kin_.get(), &nje);
    stats.steps = nni;
    stats.nonlinear_iters = nni;
    stats.linear_setups = nje;
    stats.rhs_evals = ev_.rhs_evals;
    stats.jac_evals = ev_.jac_evals;
  }

private:
  /// Residuals are scaled by 1/|dF_i/dT_i| (K/W): each reads as the temperature change of node i
  /// that would balance it, so one tolerance in kelvin fits small and large heat flows alike.
  void scale_residuals() {
    double* fs = NV_DATA_S(fscale_.get());
    std::fill(fs, fs + n_, 1.0);
    if (ev_.jacobian(t_, NV_DATA_S(u_.get())) == 0) {
      for (int i = 0; i < n_; ++i) {
        const double g = std::abs(ev_.jacobian_storage().diagonal(i));
        if (g > 0.0 && std::isfinite(g)) fs[i] = 1.0 / g;
      }
    } else if (ev_.pending) {
      std::rethrow_exception(ev_.pending);
    }
  }

  /// The user data, the linear solver, the tolerances (residuals below kResidualFraction * atol,
  /// steps below kStepFraction * atol), exact Newton, the iteration cap and the constraints.
  void configure(LinearSolverKind kind, const SolverOptions& opt, bool positive) {
    void* mem = kin_.get();
    chk_.call(Api::kinsol, "KINSetErrHandlerFn", KINSetErrHandlerFn, mem,
              &sundials::Checker::handler, static_cast<void*>(&chk_));
    chk_.call(Api::kinsol, "KINInit", KINInit, mem, kin_func, u_.get());
    chk_.call(Api::kinsol, "KINSetUserData", KINSetUserData, mem, static_cast<void*>(&data_));
    ls_ = detail::make_linear_system(kind, ev_.jacobian_storage(), u_.get(), ctx_.get(), chk_);
    chk_.call(Api::kinsol_ls, "KINSetLinearSolver", KINSetLinearSolver, mem, ls_.solver.get(),
              ls_.matrix.get());
    chk_.call(Api::kinsol_ls, "KINSetJacFn", KINSetJacFn, mem, kin_jac);
    chk_.call(Api::kinsol, "KINSetFuncNormTol", KINSetFuncNormTol, mem,
              kResidualFraction * opt.atol);
    // KINSOL measures steps relative to |T| + 1/uscale; express kStepFraction * atol in kelvin.
    const double t_max = N_VMaxNorm(u_.get());
    chk_.call(Api::kinsol, "KINSetScaledStepTol", KINSetScaledStepTol, mem,
              kStepFraction * opt.atol / (1.0 + t_max));
    chk_.call(Api::kinsol, "KINSetMaxSetupCalls", KINSetMaxSetupCalls, mem, 1L); // exact Newton
    chk_.call(Api::kinsol, "KINSetNumMaxIters", KINSetNumMaxIters, mem,
              std::min(opt.max_steps, kMaxNewtonIterations));
    if (positive)
      chk_.call(Api::kinsol, "KINSetConstraints", KINSetConstraints, mem, constraints_.get());
  }

  /// One Newton solve from the current iterate; throws SolverError when it finds no solution.
  void newton(const SolverOptions& opt) {
    ev_.clear_nonfinite();
    const int flag = chk_.check(
        Api::kinsol, KINSol(kin_.get(), u_.get(), KIN_LINESEARCH, uscale_.get(), fscale_.get()),
        "KINSol");
    if (flag == KIN_STEP_LT_STPTOL && !(largest_scaled_residual() <= opt.atol))
      chk_.fail("KINSol", flag, sundials::flag_name(Api::kinsol, flag),
                sundials::flag_description(Api::kinsol, flag));
  }

  /// The largest residual at the current iterate as a temperature (infinite when the heat balance
  /// cannot be evaluated): steps that became negligible are accepted only when it is small too.
  double largest_scaled_residual() {
    const double* fs = NV_DATA_S(fscale_.get());
    std::vector<double> f(static_cast<std::size_t>(n_));
    double worst = 0.0;
    if (ev_.heat_balance(t_, NV_DATA_S(u_.get()), f.data()) == 0)
      for (int i = 0; i < n_; ++i)
        worst = std::max(worst, std::abs(f[static_cast<std::size_t>(i)]) * fs[i]);
    else
      worst = HUGE_VAL;
    return worst;
  }

  /// The nodes with the largest scaled residuals, and the nodes with no conductance to anything.
  sundials::FailureReport failure_report() {
    sundials::FailureReport d;
    d.time = t_;
    d.note = ev_.describe_nonfinite();
    const double* fs = NV_DATA_S(fscale_.get());
    std::vector<double> f(static_cast<std::size_t>(n_));
    if (ev_.heat_balance(t_, NV_DATA_S(u_.get()), f.data()) >= 0) {
      for (int i = 0; i < n_; ++i)
        f[static_cast<std::size_t>(i)] *= fs[i];
      d.worst = ev_.worst_unknowns(f.data());
    }
    ev_.pending = nullptr;
    const std::vector<std::string> loose = ev_.zero_diagonal_unknowns(false);
    if (!loose.empty()) {
      if (!d.note.empty()) d.note += "; ";
      d.note +=
          fmt::format("{} {} {} no conductance to anything", loose.size() == 1 ? "node" : "nodes",
                      fmt::join(loose, ", "), loose.size() == 1 ? "has" : "have");
      for (auto it = loose.rbegin(); it != loose.rend(); ++it)
        if (std::find(d.worst.begin(), d.worst.end(), *it) == d.worst.end())
          d.worst.insert(d.worst.begin(), *it);
    }
    d.worst_label = "largest residuals at nodes";
    return d;
  }

  detail::SystemEvaluator& ev_;
  double t_;
  int n_;
  LinearSolverKind kind_;
  sundials::Checker chk_{"KINSOL"};
  sundials::Context ctx_;
  sundials::NVector u_;
  sundials::NVector uscale_;
  sundials::NVector fscale_;
  sundials::NVector constraints_;
  SteadyData data_;
  bool positive_; // the iterates are kept above 0 K
  sundials::KinsolMemory kin_;
  detail::LinearSystem ls_;
};

} // namespace

SolverStats solve_steady(ThermalSystem& sys, std::vector<double>& T, double t,
                         const SolverOptions& opt) {
  detail::SystemEvaluator ev(sys);
  const int n = ev.size();
  if (T.size() != static_cast<std::size_t>(n))
    throw std::invalid_argument(
        fmt::format("solve_steady: {} initial temperatures for {} unknowns", T.size(), n));
  if (!(opt.atol > 0.0)) throw std::invalid_argument("solve_steady: atol must be positive");
  LinearSolverKind kind = detail::resolve_linear_solver(opt.linear_solver, n, opt.dense_threshold,
                                                        opt.krylov_threshold);
  if (kind == LinearSolverKind::krylov) kind = LinearSolverKind::klu; // direct Newton is cheaper

  SolverStats stats;
  stats.integrator = "kinsol";
  stats.linear_solver = detail::linear_solver_name(kind);
  if (n == 0) return stats;
  SteadyProblem problem(ev, t, T, kind, opt);
  try {
    problem.solve(T, opt);
    problem.collect(stats);
  } catch (const SolverError&) {
    // Newton finds no way from the guess (a steady state far from it, couplings of very different
    // strengths): walk toward it in pseudo-time and let Newton finish from there. When that fails
    // too, the first failure is the one reported.
    const std::exception_ptr first = std::current_exception();
    std::vector<double> walked = T;
    if (!detail::pseudo_transient(ev, walked, t, opt)) std::rethrow_exception(first);
    try {
      SteadyProblem polish(ev, t, walked, kind, opt);
      polish.solve(walked, opt);
      polish.collect(stats);
    } catch (const SolverError&) {
      std::rethrow_exception(first);
    }
    T = std::move(walked);
    stats.integrator = "kinsol+pseudo-transient";
  }
  return stats;
}

} // namespace thermnet
