// IDA stepper for systems with algebraic (zero-capacity) nodes: residual C T' - F(t, T) = 0.

#include "kernel/core/absolute_zero.hpp"
#include "kernel/core/fast_kernels.hpp"
#include "kernel/core/sundials_stepper.hpp"

#include <ida/ida.h>
#include <ida/ida_ls.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <fmt/format.h>

#include <algorithm>
#include <vector>

namespace thermnet::detail {

namespace {

using sundials::Api;

/// Newton iterations (one Jacobian each) of the exact-Newton retry of IDACalcIC.
constexpr int kExactNewtonIterationsIC = 100;

SystemEvaluator& evaluator(void* user_data) {
  return *static_cast<SystemEvaluator*>(user_data);
}

/// The Newton matrix of IDA: -dF/dT + cj diag(C).
Combination newton_matrix(SystemEvaluator& ev, double cj) {
  return Combination{-1.0, nullptr, cj, ev.capacities().data()};
}

/// r = C T' - F(t, T).
int ida_residual(sunrealtype t, N_Vector y, N_Vector yp, N_Vector r, void* user_data) {
  SystemEvaluator& ev = evaluator(user_data);
  double* res = NV_DATA_S(r);
  if (const int status = ev.heat_balance(t, NV_DATA_S(y), res); status != 0) return status;
  const double* c = ev.capacities().data();
  const double* tp = NV_DATA_S(yp);
  const int n = ev.size();
  for (int i = 0; i < n; ++i)
    res[i] = c[i] * tp[i] - res[i];
  return 0;
}

int ida_jacobian(sunrealtype t, sunrealtype cj, N_Vector y, N_Vector /*yp*/, N_Vector /*r*/,
                 SUNMatrix J, void* user_data, N_Vector, N_Vector, N_Vector) {
  SystemEvaluator& ev = evaluator(user_data);
  if (const int status = ev.jacobian(t, NV_DATA_S(y)); status != 0) return status;
  SparseJacobian& jac = ev.jacobian_storage();
  if (SUNMatGetID(J) == SUNMATRIX_DENSE) {
    jac.fill_dense(J, newton_matrix(ev, cj));
  } else {
    jac.copy_pattern(J); // IDA zeroes the whole sparse matrix, index arrays included
    jac.fill_sparse_values(J, newton_matrix(ev, cj));
  }
  return 0;
}

int ida_psetup(sunrealtype t, N_Vector y, N_Vector /*yp*/, N_Vector /*r*/, sunrealtype cj,
               void* user_data) {
  SystemEvaluator& ev = evaluator(user_data);
  if (const int status = ev.jacobian(t, NV_DATA_S(y)); status != 0) return status;
  return ev.jacobian_storage().factor_ilu(newton_matrix(ev, cj)) ? 0 : 1;
}

int ida_psolve(sunrealtype /*t*/, N_Vector /*y*/, N_Vector /*yp*/, N_Vector /*r*/, N_Vector rv,
               N_Vector zv, sunrealtype /*cj*/, sunrealtype /*delta*/, void* user_data) {
  evaluator(user_data).jacobian_storage().solve_ilu(NV_DATA_S(rv), NV_DATA_S(zv));
  return 0;
}

/// Jv = (-dF/dT + cj diag(C)) v with the Jacobian of the last preconditioner setup.
int ida_jtimes(sunrealtype /*t*/, N_Vector /*y*/, N_Vector /*yp*/, N_Vector /*r*/, N_Vector v,
               N_Vector Jv, sunrealtype cj, void* user_data, N_Vector, N_Vector) {
  SystemEvaluator& ev = evaluator(user_data);
  ev.jacobian_storage().multiply(newton_matrix(ev, cj), NV_DATA_S(v), NV_DATA_S(Jv));
  return 0;
}

int ida_events(sunrealtype t, N_Vector y, N_Vector /*yp*/, sunrealtype* g, void* user_data) {
  return evaluator(user_data).events(t, NV_DATA_S(y), g);
}

const IntegratorApi kIda{.api = Api::ida,
                         .name = "ida",
                         .root_return = IDA_ROOT_RETURN,
                         .tstop_return = IDA_TSTOP_RETURN,
                         .too_much_work = IDA_TOO_MUCH_WORK,
                         .repeated_rhs = IDA_REP_RES_ERR,
                         .success = IDA_SUCCESS,
                         .num_steps = IDAGetNumSteps,
                         .num_lin_solv_setups = IDAGetNumLinSolvSetups,
                         .num_err_test_fails = IDAGetNumErrTestFails,
                         .nonlin_solv_stats = IDAGetNonlinSolvStats,
                         .num_lin_iters = IDAGetNumLinIters,
                         .current_time = IDAGetCurrentTime,
                         .err_weights = IDAGetErrWeights,
                         .est_local_errors = IDAGetEstLocalErrors,
                         .dky = IDAGetDky,
                         .dky_name = "IDAGetDky",
                         .root_info = IDAGetRootInfo,
                         .root_info_name = "IDAGetRootInfo"};

class IdaStepper final : public SundialsStepper {
public:
  IdaStepper(SystemEvaluator& ev, LinearSolverKind kind, const SolverOptions& opt, double t0,
             const double* T0, double stop)
      : SundialsStepper(kIda, "IDA", ev, kind) {
    create_state(T0);
    const SUNContext ctx = ctx_.get();
    yp_.reset(chk_.created(N_VNew_Serial(n_, ctx), "N_VNew_Serial"));
    id_.reset(chk_.created(N_VNew_Serial(n_, ctx), "N_VNew_Serial"));
    accelerate_vector(yp_.get());
    accelerate_vector(id_.get());
    const std::vector<double>& c = ev_.capacities();
    double* id = NV_DATA_S(id_.get());
    for (int i = 0; i < n_; ++i)
      id[i] = c[static_cast<std::size_t>(i)] > 0.0 ? 1.0 : 0.0;
    initial_derivative_guess(t0, T0, stop);

    mem_.reset(chk_.created(IDACreate(ctx), "IDACreate"));
    void* mem = mem_.get();
    chk_.call(Api::ida, "IDASetErrHandlerFn", IDASetErrHandlerFn, mem, &sundials::Checker::handler,
              static_cast<void*>(&chk_));
    chk_.call(Api::ida, "IDAInit", IDAInit, mem, ida_residual, t0, y_.get(), yp_.get());
    chk_.call(Api::ida, "IDASStolerances", IDASStolerances, mem, opt.rtol, opt.atol);
    chk_.call(Api::ida, "IDASetUserData", IDASetUserData, mem, static_cast<void*>(&ev_));
    chk_.call(Api::ida, "IDASetMaxNumSteps", IDASetMaxNumSteps, mem, opt.max_steps);
    if (opt.max_step > 0.0) chk_.call(Api::ida, "IDASetMaxStep", IDASetMaxStep, mem, opt.max_step);
    chk_.call(Api::ida, "IDASetId", IDASetId, mem, id_.get());

    ls_ = make_linear_system(kind_, ev_.jacobian_storage(), y_.get(), ctx, chk_);
    chk_.call(Api::ida_ls, "IDASetLinearSolver", IDASetLinearSolver, mem, ls_.solver.get(),
              ls_.matrix.get());
    if (kind_ == LinearSolverKind::krylov) {
      chk_.call(Api::ida_ls, "IDASetJacTimes", IDASetJacTimes, mem, nullptr, ida_jtimes);
      chk_.call(Api::ida_ls, "IDASetPreconditioner", IDASetPreconditioner, mem, ida_psetup,
                ida_psolve);
    } else {
      chk_.call(Api::ida_ls, "IDASetJacFn", IDASetJacFn, mem, ida_jacobian);
    }

    if (!roots_.empty()) {
      chk_.call(Api::ida, "IDARootInit", IDARootInit, mem, static_cast<int>(roots_.size()),
                ida_events);
      chk_.call(Api::ida, "IDASetNoInactiveRootWarn", IDASetNoInactiveRootWarn, mem);
    }
    chk_.call(Api::ida, "IDASetStopTime", IDASetStopTime, mem, stop);
    consistent_initial_conditions(t0, stop);
  }

  void restart(double t, double stop) override {
    accumulate();
    ev_.set_window(t, stop);
    chk_.call(Api::ida, "IDAReInit", IDAReInit, mem_.get(), t, y_.get(), yp_.get());
    chk_.call(Api::ida, "IDASetStopTime", IDASetStopTime, mem_.get(), stop);
    consistent_initial_conditions(t, stop);
  }

  StepResult step(double stop, double& t) override {
    started_ = true;
    return outcome(chk_.check(
        Api::ida, IDASolve(mem_.get(), stop, &t, y_.get(), yp_.get(), IDA_ONE_STEP), "IDASolve"));
  }

  void derivative(double* out) override {
    const double* tp = NV_DATA_S(yp_.get());
    std::copy(tp, tp + n_, out);
  }

private:
  void* memory() const override { return mem_.get(); }

  /// Initial guess of T': F/C on capacitive nodes (IDACalcIC corrects it), 0 on algebraic ones.
  void initial_derivative_guess(double t0, const double* T0, double stop) {
    ev_.set_window(t0, stop);
    double* tp = NV_DATA_S(yp_.get());
    if (ev_.heat_balance(t0, T0, tp) == 0) {
      const std::vector<double>& inv_c = ev_.inverse_capacities();
      for (int i = 0; i < n_; ++i)
        tp[i] *= inv_c[static_cast<std::size_t>(i)];
    } else {
      std::fill(tp, tp + n_, 0.0);
      ev_.pending = nullptr; // IDACalcIC will meet the same failure and report it
    }
  }

  /// Algebraic temperatures and all T' consistent with the differential temperatures at time t.
  /// T^4 has a negative root too: from a start above 0 K the search stays there (the physical
  /// root), first with IDA's modified Newton, then, should that fail, with exact Newton (a fresh
  /// Jacobian every iteration: the T^4 slope changes by orders of magnitude on the way). Should
  /// that fail too, an unconstrained search tells whether the state lies below 0 K (a failure
  /// naming the node). While stepping, the driver reports a temperature going below 0 K.
  void consistent_initial_conditions(double t, double stop) {
    void* mem = mem_.get();
    const int temps = ev_.system().temperature_count();
    const double* y0 = NV_DATA_S(y_.get());
    const bool positive = std::all_of(y0, y0 + temps, [](double T) { return T > 0.0; });
    if (positive) {
      if (!positive_) {
        positive_.reset(chk_.created(N_VNew_Serial(n_, ctx_.get()), "N_VNew_Serial"));
        N_VConst(0.0, positive_.get()); // accounts (energies) unconstrained
        std::fill(NV_DATA_S(positive_.get()), NV_DATA_S(positive_.get()) + temps, 2.0);
        y_start_.reset(chk_.created(N_VClone(y_.get()), "N_VClone"));
        yp_start_.reset(chk_.created(N_VClone(yp_.get()), "N_VClone"));
      }
      N_VScale(1.0, y_.get(), y_start_.get());
      N_VScale(1.0, yp_.get(), yp_start_.get());
      int flag = calc_ic(stop, true, false);
      if (flag < 0) flag = calc_ic_again(t, stop, true, true);
      if (flag < 0) calc_ic_again(t, stop, false, true);
    } else {
      chk_.check(Api::ida, calc_ic(stop, false, false), "IDACalcIC");
    }
    chk_.call(Api::ida, "IDAGetConsistentIC", IDAGetConsistentIC, mem, y_.get(), yp_.get());
    const double* y = NV_DATA_S(y_.get());
    if (const int i = coldest_below_absolute_zero(y, ev_.system().temperature_count()); i >= 0)
      fail_below_absolute_zero(
          ev_, {.unknown = i, .crossing = t, .kelvin = y[i], .reached = t, .steady = false},
          "IDACalcIC");
  }

  /// IDACalcIC from the current start, kept above 0 K or not, with exact Newton or IDA's default
  /// (up to 10 iterations per Jacobian); returns its flag unchecked.
  int calc_ic(double stop, bool constrained, bool exact) {
    void* mem = mem_.get();
    chk_.call(Api::ida, "IDASetConstraints", IDASetConstraints, mem,
              constrained ? positive_.get() : nullptr);
    chk_.call(Api::ida, "IDASetMaxNumItersIC", IDASetMaxNumItersIC, mem, exact ? 1 : 10);
    chk_.call(Api::ida, "IDASetMaxNumJacsIC", IDASetMaxNumJacsIC, mem,
              exact ? kExactNewtonIterationsIC : 4);
    const int flag = IDACalcIC(mem, IDA_YA_YDP_INIT, stop);
    chk_.call(Api::ida, "IDASetConstraints", IDASetConstraints, mem, nullptr);
    return flag;
  }

  /// calc_ic() again from the start saved by consistent_initial_conditions(); the last attempt
  /// (unconstrained) has its failure thrown.
  int calc_ic_again(double t, double stop, bool constrained, bool exact) {
    void* mem = mem_.get();
    chk_.call(Api::ida, "IDAReInit", IDAReInit, mem, t, y_start_.get(), yp_start_.get());
    chk_.call(Api::ida, "IDASetStopTime", IDASetStopTime, mem, stop);
    const int flag = calc_ic(stop, constrained, exact);
    return constrained ? flag : chk_.check(Api::ida, flag, "IDACalcIC");
  }

  /// Consistent initial conditions failed: names the arithmetic nodes connected to nothing, the
  /// likely cause of a singular system.
  void explain_start_failure(sundials::FailureReport& d) const override {
    const std::vector<std::string> loose = ev_.zero_diagonal_unknowns(true);
    if (loose.empty()) return;
    if (!d.note.empty()) d.note += "; ";
    d.note += fmt::format("{} {} {} no conductance to anything",
                          loose.size() == 1 ? "arithmetic node" : "arithmetic nodes",
                          fmt::join(loose, ", "), loose.size() == 1 ? "has" : "have");
    d.worst = loose;
  }

  sundials::NVector yp_;
  sundials::NVector id_;
  sundials::NVector positive_; // the constraint T > 0 of consistent_initial_conditions()
  sundials::NVector y_start_;  // its starting state, for the unconstrained retry
  sundials::NVector yp_start_; // and starting T'
  sundials::IdaMemory mem_;
};

} // namespace

std::unique_ptr<TransientStepper> make_ida_stepper(SystemEvaluator& ev, LinearSolverKind kind,
                                                   const SolverOptions& opt, double t0,
                                                   const double* T0, double stop) {
  return std::make_unique<IdaStepper>(ev, kind, opt, t0, T0, stop);
}

} // namespace thermnet::detail
