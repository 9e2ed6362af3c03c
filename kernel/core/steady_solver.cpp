// solve_steady(): F(t, T) = 0 by KINSOL's Newton method with line search and the analytic Jacobian.

#include "kernel/core/integrator.hpp"

#include "kernel/core/fast_kernels.hpp"
#include "kernel/core/linear_solver_choice.hpp"
#include "kernel/core/sundials_check.hpp"
#include "kernel/core/system_evaluator.hpp"

#include <kinsol/kinsol.h>
#include <kinsol/kinsol_ls.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

  sundials::Checker chk("KINSOL");
  chk.steady = true;
  chk.pending = &ev.pending;
  sundials::Context ctx;
  const SUNContext sc = ctx.get();
  sundials::NVector u(chk.created(N_VNew_Serial(n, sc), "N_VNew_Serial"));
  sundials::NVector uscale(chk.created(N_VNew_Serial(n, sc), "N_VNew_Serial"));
  sundials::NVector fscale(chk.created(N_VNew_Serial(n, sc), "N_VNew_Serial"));
  sundials::NVector constraints(chk.created(N_VNew_Serial(n, sc), "N_VNew_Serial"));
  for (N_Vector v : {u.get(), uscale.get(), fscale.get(), constraints.get()})
    detail::accelerate_vector(v);
  double* uu = NV_DATA_S(u.get());
  std::copy(T.begin(), T.end(), uu);
  N_VConst(1.0, uscale.get());

  // Residuals are scaled by 1/|dF_i/dT_i| (K/W): each reads as the temperature change of node i
  // that would balance it, so one tolerance in kelvin fits small and large heat flows alike.
  double* fs = NV_DATA_S(fscale.get());
  std::fill(fs, fs + n, 1.0);
  if (ev.jacobian(t, uu) == 0) {
    for (int i = 0; i < n; ++i) {
      const double g = std::abs(ev.jacobian_storage().diagonal(i));
      if (g > 0.0 && std::isfinite(g)) fs[i] = 1.0 / g;
    }
  } else if (ev.pending) {
    std::rethrow_exception(ev.pending);
  }

  // Temperatures are absolute: keep the iterates above 0 K when the guess is.
  const bool positive = std::all_of(T.begin(), T.end(), [](double x) { return x > 0.0; });
  N_VConst(positive ? 2.0 : 0.0, constraints.get());

  SteadyData data{&ev, t};
  sundials::KinsolMemory kin(chk.created(KINCreate(sc), "KINCreate"));
  void* mem = kin.get();
  const auto worst_residuals = [&]() {
    sundials::FailureReport d;
    d.time = t;
    d.note = ev.describe_nonfinite();
    std::vector<double> f(static_cast<std::size_t>(n));
    if (ev.heat_balance(t, uu, f.data()) >= 0) {
      for (int i = 0; i < n; ++i)
        f[static_cast<std::size_t>(i)] *= fs[i];
      d.worst = ev.worst_unknowns(f.data());
    }
    ev.pending = nullptr;
    const std::vector<std::string> loose = ev.zero_diagonal_unknowns(false);
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
  };
  chk.describe_failure = worst_residuals;
  chk.call(Api::kinsol, "KINSetErrHandlerFn", KINSetErrHandlerFn, mem, &sundials::Checker::handler,
           static_cast<void*>(&chk));
  chk.call(Api::kinsol, "KINInit", KINInit, mem, kin_func, u.get());
  chk.call(Api::kinsol, "KINSetUserData", KINSetUserData, mem, static_cast<void*>(&data));
  detail::LinearSystem ls =
      detail::make_linear_system(kind, ev.jacobian_storage(), u.get(), sc, chk);
  chk.call(Api::kinsol_ls, "KINSetLinearSolver", KINSetLinearSolver, mem, ls.solver.get(),
           ls.matrix.get());
  chk.call(Api::kinsol_ls, "KINSetJacFn", KINSetJacFn, mem, kin_jac);
  chk.call(Api::kinsol, "KINSetFuncNormTol", KINSetFuncNormTol, mem, kResidualFraction * opt.atol);
  // KINSOL measures steps relative to |T| + 1/uscale; express kStepFraction * atol in kelvin.
  const double t_max = N_VMaxNorm(u.get());
  chk.call(Api::kinsol, "KINSetScaledStepTol", KINSetScaledStepTol, mem,
           kStepFraction * opt.atol / (1.0 + t_max));
  chk.call(Api::kinsol, "KINSetMaxSetupCalls", KINSetMaxSetupCalls, mem, 1L); // exact Newton
  chk.call(Api::kinsol, "KINSetNumMaxIters", KINSetNumMaxIters, mem,
           std::min(opt.max_steps, kMaxNewtonIterations));
  if (positive)
    chk.call(Api::kinsol, "KINSetConstraints", KINSetConstraints, mem, constraints.get());

  ev.clear_nonfinite();
  const int flag = chk.check(
      Api::kinsol, KINSol(mem, u.get(), KIN_LINESEARCH, uscale.get(), fscale.get()), "KINSol");
  if (flag == KIN_STEP_LT_STPTOL) {
    // Steps became negligible: accept only if the residual is small as well.
    std::vector<double> f(static_cast<std::size_t>(n));
    double worst = 0.0;
    if (ev.heat_balance(t, uu, f.data()) == 0)
      for (int i = 0; i < n; ++i)
        worst = std::max(worst, std::abs(f[static_cast<std::size_t>(i)]) * fs[i]);
    else
      worst = HUGE_VAL;
    if (!(worst <= opt.atol))
      chk.fail("KINSol", flag, sundials::flag_name(Api::kinsol, flag),
               sundials::flag_description(Api::kinsol, flag));
  }
  std::copy(uu, uu + n, T.begin());

  long nni = 0, nje = 0;
  KINGetNumNonlinSolvIters(mem, &nni);
  KINGetNumJacEvals(mem, &nje);
  stats.steps = nni;
  stats.nonlinear_iters = nni;
  stats.linear_setups = nje;
  stats.rhs_evals = ev.rhs_evals;
  stats.jac_evals = ev.jac_evals;
  return stats;
}

} // namespace thermnet
