// CVODE BDF stepper for systems whose every node has a heat capacity: dT/dt = F(t, T) / C.

#include "kernel/core/fast_kernels.hpp"
#include "kernel/core/linear_solver_choice.hpp"
#include "kernel/core/transient_stepper.hpp"

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

class CvodeStepper final : public TransientStepper {
public:
  CvodeStepper(SystemEvaluator& ev, LinearSolverKind kind, const SolverOptions& opt, double t0,
               const double* T0, double stop)
      : ev_(ev), kind_(kind), n_(ev.size()), t_restart_(t0) {
    chk_.pending = &ev_.pending;
    chk_.describe_failure = [this] { return failure_report(); };
    const SUNContext ctx = ctx_.get();
    y_.reset(chk_.created(N_VNew_Serial(n_, ctx), "N_VNew_Serial"));
    out_.reset(chk_.created(N_VNewEmpty_Serial(n_, ctx), "N_VNewEmpty_Serial"));
    accelerate_vector(y_.get()); // before CVodeInit and the solvers clone it
    accelerate_vector(out_.get());
    std::copy(T0, T0 + n_, NV_DATA_S(y_.get()));

    mem_.reset(chk_.created(CVodeCreate(CV_BDF, ctx), "CVodeCreate"));
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

    ls_ = make_linear_system(kind_, ev_.jacobian_storage(), y_.get(), ctx, chk_);
    chk_.call(Api::cvode_ls, "CVodeSetLinearSolver", CVodeSetLinearSolver, mem, ls_.solver.get(),
              ls_.matrix.get());
    if (kind_ == LinearSolverKind::krylov) {
      chk_.call(Api::cvode_ls, "CVodeSetJacTimes", CVodeSetJacTimes, mem, nullptr, cv_jtimes);
      chk_.call(Api::cvode_ls, "CVodeSetPreconditioner", CVodeSetPreconditioner, mem, cv_psetup,
                cv_psolve);
    } else {
      chk_.call(Api::cvode_ls, "CVodeSetLinSysFn", CVodeSetLinSysFn, mem, cv_linsys);
    }

    const int nev = ev_.system().event_count();
    if (nev > 0) {
      roots_.assign(static_cast<std::size_t>(nev), 0);
      chk_.call(Api::cvode, "CVodeRootInit", CVodeRootInit, mem, nev, cv_events);
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
    const int flag =
        chk_.check(Api::cvode, CVode(mem_.get(), stop, y_.get(), &t, CV_ONE_STEP), "CVode");
    if (flag == CV_ROOT_RETURN) {
      chk_.call(Api::cvode, "CVodeGetRootInfo", CVodeGetRootInfo, mem_.get(), roots_.data());
      return StepResult::root_found;
    }
    if (flag == CV_TSTOP_RETURN) return StepResult::stop_reached;
    return StepResult::advanced;
  }

  void interpolate(double t, double* out) override {
    N_VSetArrayPointer(out, out_.get());
    chk_.call(Api::cvode, "CVodeGetDky", CVodeGetDky, mem_.get(), t, 0, out_.get());
  }

  void derivative(double* out) override {
    N_VSetArrayPointer(out, out_.get());
    if (cv_rhs(t_restart_, y_.get(), out_.get(), &ev_) != 0) std::fill(out, out + n_, 0.0);
    ev_.pending = nullptr;
  }

  double* state() override { return NV_DATA_S(y_.get()); }
  const int* roots() override { return roots_.data(); }

  long steps() override {
    long nst = 0;
    CVodeGetNumSteps(mem_.get(), &nst);
    return acc_.steps + nst;
  }

  void collect(SolverStats& stats) override {
    accumulate();
    stats.integrator = "cvode-bdf";
    stats.linear_solver = linear_solver_name(kind_);
    add_counters(stats, acc_, ev_.rhs_evals, ev_.jac_evals);
    stats.prec_setups += ev_.jacobian_storage().ilu_factorizations();
    acc_ = SolverStats{};
  }

  sundials::Checker& checker() override { return chk_; }
  int too_much_work_flag() const override { return CV_TOO_MUCH_WORK; }
  int repeated_rhs_flag() const override { return CV_REPTD_RHSFUNC_ERR; }
  std::string flag_name(int flag) const override { return sundials::flag_name(Api::cvode, flag); }

private:
  /// Adds the counters of the current segment (CVodeReInit resets CVODE's own).
  void accumulate() {
    void* mem = mem_.get();
    long nst = 0, nsetups = 0, netf = 0, nni = 0, ncfn = 0;
    CVodeGetNumSteps(mem, &nst);
    CVodeGetNumLinSolvSetups(mem, &nsetups);
    CVodeGetNumErrTestFails(mem, &netf);
    CVodeGetNonlinSolvStats(mem, &nni, &ncfn);
    acc_.steps += nst;
    acc_.linear_setups += nsetups;
    acc_.error_test_fails += netf;
    acc_.nonlinear_iters += nni;
    acc_.nonlinear_fails += ncfn;
    if (kind_ == LinearSolverKind::krylov) {
      long nli = 0;
      CVodeGetNumLinIters(mem, &nli);
      acc_.linear_iters += nli;
    }
  }

  /// Time reached, and the unknowns with the largest weighted local error estimates.
  sundials::FailureReport failure_report() {
    sundials::FailureReport d;
    void* mem = mem_.get();
    CVodeGetCurrentTime(mem, &d.time);
    d.note = ev_.describe_nonfinite();
    if (ev_.nonfinite().seen) d.worst.push_back(ev_.name(ev_.nonfinite().index));
    if (started_) {
      std::vector<double> w(static_cast<std::size_t>(n_)), e(static_cast<std::size_t>(n_));
      sundials::NVector wv(N_VMake_Serial(n_, w.data(), ctx_.get()));
      sundials::NVector ev_vec(N_VMake_Serial(n_, e.data(), ctx_.get()));
      if (wv && ev_vec && CVodeGetErrWeights(mem, wv.get()) == CV_SUCCESS &&
          CVodeGetEstLocalErrors(mem, ev_vec.get()) == CV_SUCCESS) {
        for (std::size_t i = 0; i < w.size(); ++i)
          e[i] *= w[i];
        for (std::string& name : ev_.worst_unknowns(e.data()))
          if (d.worst.empty() || d.worst.front() != name) d.worst.push_back(std::move(name));
      }
    }
    d.worst_label = "largest local errors at nodes";
    return d;
  }

  SystemEvaluator& ev_;
  LinearSolverKind kind_;
  int n_;
  sundials::Checker chk_{"CVODE"};
  sundials::Context ctx_;
  sundials::NVector y_;
  sundials::NVector out_;
  LinearSystem ls_;
  sundials::CvodeMemory mem_;
  std::vector<int> roots_;
  SolverStats acc_;
  bool started_ = false;
  double t_restart_ = 0.0;
};

} // namespace

std::unique_ptr<TransientStepper> make_cvode_stepper(SystemEvaluator& ev, LinearSolverKind kind,
                                                     const SolverOptions& opt, double t0,
                                                     const double* T0, double stop) {
  return std::make_unique<CvodeStepper>(ev, kind, opt, t0, T0, stop);
}

} // namespace thermnet::detail
