// CVODE BDF stepper for systems whose every node has a heat capacity: dT/dt = F(t, T) / C.

#include "kernel/core/fast_kernels.hpp"
#include "kernel/core/sundials_stepper.hpp"

#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <vector>

namespace thermnet::detail {

namespace {

using sundials::Api;

SystemEvaluator& evaluator(void* user_data) {
  return *static_cast<SystemEvaluator*>(user_data);
}

/// dT/dt = F / C.
int cv_rhs(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data) {
  SystemEvaluator& ev = evaluator(user_data);
  double* f = NV_DATA_S(ydot);
  if (const int r = ev.heat_balance(t, NV_DATA_S(y), f); r != 0) return r;
  const double* inv_c = ev.inverse_capacities().data();
  const int n = ev.size();
  for (int i = 0; i < n; ++i)
    f[i] *= inv_c[i];
  return 0;
}

/// Updates dF/dT unless CVODE says the saved one is still good.
int update_jacobian(SystemEvaluator& ev, sunrealtype t, N_Vector y, sunbooleantype jok,
                    sunbooleantype* jcur) {
  if (jok) {
    *jcur = SUNFALSE;
    return 0;
  }
  *jcur = SUNTRUE;
  return ev.jacobian(t, NV_DATA_S(y));
}

/// The Newton matrix I - gamma diag(1/C) dF/dT, filled straight into A (dense or sparse CSR).
int cv_linsys(sunrealtype t, N_Vector y, N_Vector /*fy*/, SUNMatrix A, sunbooleantype jok,
              sunbooleantype* jcur, sunrealtype gamma, void* user_data, N_Vector, N_Vector,
              N_Vector) {
  SystemEvaluator& ev = evaluator(user_data);
  if (const int r = update_jacobian(ev, t, y, jok, jcur); r != 0) return r;
  const Combination m{-gamma, ev.inverse_capacities().data(), 1.0, nullptr};
  if (SUNMatGetID(A) == SUNMATRIX_DENSE)
    ev.jacobian_storage().fill_dense(A, m);
  else
    ev.jacobian_storage().fill_sparse_values(A, m);
  return 0;
}

/// Jv = diag(1/C) dF/dT v with the Jacobian of the last preconditioner setup.
int cv_jtimes(N_Vector v, N_Vector Jv, sunrealtype /*t*/, N_Vector /*y*/, N_Vector /*fy*/,
              void* user_data, N_Vector /*tmp*/) {
  SystemEvaluator& ev = evaluator(user_data);
  const Combination j{1.0, ev.inverse_capacities().data(), 0.0, nullptr};
  ev.jacobian_storage().multiply(j, NV_DATA_S(v), NV_DATA_S(Jv));
  return 0;
}

/// ILU(0) of I - gamma diag(1/C) dF/dT.
int cv_psetup(sunrealtype t, N_Vector y, N_Vector /*fy*/, sunbooleantype jok, sunbooleantype* jcur,
              sunrealtype gamma, void* user_data) {
  SystemEvaluator& ev = evaluator(user_data);
  if (const int r = update_jacobian(ev, t, y, jok, jcur); r != 0) return r;
  const Combination m{-gamma, ev.inverse_capacities().data(), 1.0, nullptr};
  return ev.jacobian_storage().factor_ilu(m) ? 0 : 1;
}

int cv_psolve(sunrealtype /*t*/, N_Vector /*y*/, N_Vector /*fy*/, N_Vector r, N_Vector z,
              sunrealtype /*gamma*/, sunrealtype /*delta*/, int /*lr*/, void* user_data) {
  evaluator(user_data).jacobian_storage().solve_ilu(NV_DATA_S(r), NV_DATA_S(z));
  return 0;
}

int cv_events(sunrealtype t, N_Vector y, sunrealtype* g, void* user_data) {
  return evaluator(user_data).events(t, NV_DATA_S(y), g);
}

const IntegratorApi kCvode{.api = Api::cvode,
                           .name = "cvode-bdf",
                           .root_return = CV_ROOT_RETURN,
                           .tstop_return = CV_TSTOP_RETURN,
                           .too_much_work = CV_TOO_MUCH_WORK,
                           .repeated_rhs = CV_REPTD_RHSFUNC_ERR,
                           .success = CV_SUCCESS,
                           .num_steps = CVodeGetNumSteps,
                           .num_lin_solv_setups = CVodeGetNumLinSolvSetups,
                           .num_err_test_fails = CVodeGetNumErrTestFails,
                           .nonlin_solv_stats = CVodeGetNonlinSolvStats,
                           .num_lin_iters = CVodeGetNumLinIters,
                           .current_time = CVodeGetCurrentTime,
                           .err_weights = CVodeGetErrWeights,
                           .est_local_errors = CVodeGetEstLocalErrors,
                           .dky = CVodeGetDky,
                           .dky_name = "CVodeGetDky",
                           .root_info = CVodeGetRootInfo,
                           .root_info_name = "CVodeGetRootInfo"};

class CvodeStepper final : public SundialsStepper {
public:
  CvodeStepper(SystemEvaluator& ev, LinearSolverKind kind, const SolverOptions& opt, double t0,
               const double* T0, double stop)
      : SundialsStepper(kCvode, "CVODE", ev, kind), t_restart_(t0) {
    create_state(T0);
    mem_.reset(chk_.created(CVodeCreate(CV_BDF, ctx_.get()), "CVodeCreate"));
    void* mem = mem_.get();
    chk_.call(Api::cvode, "CVodeSetErrHandlerFn", CVodeSetErrHandlerFn, mem,
              &sundials::Checker::handler, static_cast<void*>(&chk_));
    ev_.set_window(t0, stop);
    chk_.call(Api::cvode, "CVodeInit", CVodeInit, mem, cv_rhs, t0, y_.get());
    chk_.call(Api::cvode, "CVodeSStolerances", CVodeSStolerances, mem, opt.rtol, opt.atol);
    chk_.call(Api::cvode, "CVodeSetUserData", CVodeSetUserData, mem, static_cast<void*>(&ev_));
    chk_.call(Api::cvode, "CVodeSetMaxNumSteps", CVodeSetMaxNumSteps, mem, opt.max_steps);
    if (opt.max_step > 0.0)
      chk_.call(Api::cvode, "CVodeSetMaxStep", CVodeSetMaxStep, mem, opt.max_step);

    ls_ = make_linear_system(kind_, ev_.jacobian_storage(), y_.get(), ctx_.get(), chk_);
    chk_.call(Api::cvode_ls, "CVodeSetLinearSolver", CVodeSetLinearSolver, mem, ls_.solver.get(),
              ls_.matrix.get());
    if (kind_ == LinearSolverKind::krylov) {
      chk_.call(Api::cvode_ls, "CVodeSetJacTimes", CVodeSetJacTimes, mem, nullptr, cv_jtimes);
      chk_.call(Api::cvode_ls, "CVodeSetPreconditioner", CVodeSetPreconditioner, mem, cv_psetup,
                cv_psolve);
    } else {
      chk_.call(Api::cvode_ls, "CVodeSetLinSysFn", CVodeSetLinSysFn, mem, cv_linsys);
    }

    if (!roots_.empty()) {
      chk_.call(Api::cvode, "CVodeRootInit", CVodeRootInit, mem, static_cast<int>(roots_.size()),
                cv_events);
      chk_.call(Api::cvode, "CVodeSetNoInactiveRootWarn", CVodeSetNoInactiveRootWarn, mem);
    }
    chk_.call(Api::cvode, "CVodeSetStopTime", CVodeSetStopTime, mem, stop);
  }

  void restart(double t, double stop) override {
    accumulate();
    t_restart_ = t;
    ev_.set_window(t, stop);
    chk_.call(Api::cvode, "CVodeReInit", CVodeReInit, mem_.get(), t, y_.get());
    chk_.call(Api::cvode, "CVodeSetStopTime", CVodeSetStopTime, mem_.get(), stop);
  }

  StepResult step(double stop, double& t) override {
    started_ = true;
    return outcome(
        chk_.check(Api::cvode, CVode(mem_.get(), stop, y_.get(), &t, CV_ONE_STEP), "CVode"));
  }

  void derivative(double* out) override {
    N_VSetArrayPointer(out, out_.get());
    if (cv_rhs(t_restart_, y_.get(), out_.get(), &ev_) != 0) std::fill(out, out + n_, 0.0);
    ev_.pending = nullptr;
  }

private:
  void* memory() const override { return mem_.get(); }

  sundials::CvodeMemory mem_;
  double t_restart_ = 0.0;
};

} // namespace

std::unique_ptr<TransientStepper> make_cvode_stepper(SystemEvaluator& ev, LinearSolverKind kind,
                                                     const SolverOptions& opt, double t0,
                                                     const double* T0, double stop) {
  return std::make_unique<CvodeStepper>(ev, kind, opt, t0, T0, stop);
}

} // namespace thermnet::detail
