// IDA stepper for systems with algebraic (zero-capacity) nodes: residual C T' - F(t, T) = 0.

#include "kernel/core/fast_kernels.hpp"
#include "kernel/core/linear_solver_choice.hpp"
#include "kernel/core/transient_stepper.hpp"

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

class IdaStepper final : public TransientStepper {
public:
  IdaStepper(SystemEvaluator& ev, LinearSolverKind kind, const SolverOptions& opt, double t0,
             const double* T0, double stop)
      : ev_(ev), kind_(kind), n_(ev.size()) {
    chk_.pending = &ev_.pending;
    chk_.describe_failure = [this] { return failure_report(); };
    const SUNContext ctx = ctx_.get();
    y_.reset(chk_.created(N_VNew_Serial(n_, ctx), "N_VNew_Serial"));
    yp_.reset(chk_.created(N_VNew_Serial(n_, ctx), "N_VNew_Serial"));
    id_.reset(chk_.created(N_VNew_Serial(n_, ctx), "N_VNew_Serial"));
    out_.reset(chk_.created(N_VNewEmpty_Serial(n_, ctx), "N_VNewEmpty_Serial"));
    for (N_Vector v : {y_.get(), yp_.get(), id_.get(), out_.get()})
      accelerate_vector(v);
    std::copy(T0, T0 + n_, NV_DATA_S(y_.get()));
    const std::vector<double>& c = ev_.capacities();
    double* id = NV_DATA_S(id_.get());
    for (int i = 0; i < n_; ++i)
      id[i] = c[static_cast<std::size_t>(i)] > 0.0 ? 1.0 : 0.0;

    // Initial guess of T': F/C on capacitive nodes (IDACalcIC corrects it), 0 on algebraic ones.
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

    const int nev = ev_.system().event_count();
    if (nev > 0) {
      roots_.assign(static_cast<std::size_t>(nev), 0);
      chk_.call(Api::ida, "IDARootInit", IDARootInit, mem, nev, ida_events);
      chk_.call(Api::ida, "IDASetNoInactiveRootWarn", IDASetNoInactiveRootWarn, mem);
    }
    chk_.call(Api::ida, "IDASetStopTime", IDASetStopTime, mem, stop);
    consistent_initial_conditions(stop);
  }

  void restart(double t, double stop) override {
    accumulate();
    ev_.set_window(t, stop);
    chk_.call(Api::ida, "IDAReInit", IDAReInit, mem_.get(), t, y_.get(), yp_.get());
    chk_.call(Api::ida, "IDASetStopTime", IDASetStopTime, mem_.get(), stop);
    consistent_initial_conditions(stop);
  }

  StepResult step(double stop, double& t) override {
    started_ = true;
    const int flag = chk_.check(
        Api::ida, IDASolve(mem_.get(), stop, &t, y_.get(), yp_.get(), IDA_ONE_STEP), "IDASolve");
    if (flag == IDA_ROOT_RETURN) {
      chk_.call(Api::ida, "IDAGetRootInfo", IDAGetRootInfo, mem_.get(), roots_.data());
      return StepResult::root_found;
    }
    if (flag == IDA_TSTOP_RETURN) return StepResult::stop_reached;
    return StepResult::advanced;
  }

  void interpolate(double t, double* out) override {
    N_VSetArrayPointer(out, out_.get());
    chk_.call(Api::ida, "IDAGetDky", IDAGetDky, mem_.get(), t, 0, out_.get());
  }

  void derivative(double* out) override {
    const double* tp = NV_DATA_S(yp_.get());
    std::copy(tp, tp + n_, out);
  }

  double* state() override { return NV_DATA_S(y_.get()); }
  const int* roots() override { return roots_.data(); }

  long steps() override {
    long nst = 0;
    IDAGetNumSteps(mem_.get(), &nst);
    return acc_.steps + nst;
  }

  void collect(SolverStats& stats) override {
    accumulate();
    stats.integrator = "ida";
    stats.linear_solver = linear_solver_name(kind_);
    add_counters(stats, acc_, ev_.rhs_evals, ev_.jac_evals);
    stats.prec_setups += ev_.jacobian_storage().ilu_factorizations();
    acc_ = SolverStats{};
  }

  sundials::Checker& checker() override { return chk_; }
  int too_much_work_flag() const override { return IDA_TOO_MUCH_WORK; }
  int repeated_rhs_flag() const override { return IDA_REP_RES_ERR; }
  std::string flag_name(int flag) const override { return sundials::flag_name(Api::ida, flag); }

private:
  /// Algebraic temperatures and all T' consistent with the differential temperatures at the start.
  void consistent_initial_conditions(double stop) {
    void* mem = mem_.get();
    chk_.call(Api::ida, "IDACalcIC", IDACalcIC, mem, IDA_YA_YDP_INIT, stop);
    chk_.call(Api::ida, "IDAGetConsistentIC", IDAGetConsistentIC, mem, y_.get(), yp_.get());
  }

  /// Adds the counters of the current segment (IDAReInit resets IDA's own).
  void accumulate() {
    void* mem = mem_.get();
    long nst = 0, nsetups = 0, netf = 0, nni = 0, ncfn = 0;
    IDAGetNumSteps(mem, &nst);
    IDAGetNumLinSolvSetups(mem, &nsetups);
    IDAGetNumErrTestFails(mem, &netf);
    IDAGetNonlinSolvStats(mem, &nni, &ncfn);
    acc_.steps += nst;
    acc_.linear_setups += nsetups;
    acc_.error_test_fails += netf;
    acc_.nonlinear_iters += nni;
    acc_.nonlinear_fails += ncfn;
    if (kind_ == LinearSolverKind::krylov) {
      long nli = 0;
      IDAGetNumLinIters(mem, &nli);
      acc_.linear_iters += nli;
    }
  }

  sundials::FailureReport failure_report() {
    sundials::FailureReport d;
    void* mem = mem_.get();
    IDAGetCurrentTime(mem, &d.time);
    d.note = ev_.describe_nonfinite();
    if (ev_.nonfinite().seen) d.worst.push_back(ev_.name(ev_.nonfinite().index));
    if (!started_) { // consistent initial conditions failed: name suspects of a singular system
      const std::vector<std::string> loose = ev_.zero_diagonal_unknowns(true);
      if (!loose.empty()) {
        if (!d.note.empty()) d.note += "; ";
        d.note += fmt::format("{} {} {} no conductance to anything",
                              loose.size() == 1 ? "arithmetic node" : "arithmetic nodes",
                              fmt::join(loose, ", "), loose.size() == 1 ? "has" : "have");
        d.worst = loose;
      }
      return d; // the note names them; worst carries them for the caller
    }
    std::vector<double> w(static_cast<std::size_t>(n_)), e(static_cast<std::size_t>(n_));
    sundials::NVector wv(N_VMake_Serial(n_, w.data(), ctx_.get()));
    sundials::NVector ev_vec(N_VMake_Serial(n_, e.data(), ctx_.get()));
    if (wv && ev_vec && IDAGetErrWeights(mem, wv.get()) == IDA_SUCCESS &&
        IDAGetEstLocalErrors(mem, ev_vec.get()) == IDA_SUCCESS) {
      for (std::size_t i = 0; i < w.size(); ++i)
        e[i] *= w[i];
      for (std::string& name : ev_.worst_unknowns(e.data()))
        if (d.worst.empty() || d.worst.front() != name) d.worst.push_back(std::move(name));
    }
    d.worst_label = "largest local errors at nodes";
    return d;
  }

  SystemEvaluator& ev_;
  LinearSolverKind kind_;
  int n_;
  sundials::Checker chk_{"IDA"};
  sundials::Context ctx_;
  sundials::NVector y_;
  sundials::NVector yp_;
  sundials::NVector id_;
  sundials::NVector out_;
  LinearSystem ls_;
  sundials::IdaMemory mem_;
  std::vector<int> roots_;
  SolverStats acc_;
  bool started_ = false;
};

} // namespace

std::unique_ptr<TransientStepper> make_ida_stepper(SystemEvaluator& ev, LinearSolverKind kind,
                                                   const SolverOptions& opt, double t0,
                                                   const double* T0, double stop) {
  return std::make_unique<IdaStepper>(ev, kind, opt, t0, T0, stop);
}

} // namespace thermnet::detail
