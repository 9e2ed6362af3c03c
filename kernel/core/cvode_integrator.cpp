// CVODE BDF stepper for systems whose every node has a heat capacity: dT/dt = F(t, T) / C.

#include "kernel/core/fast_kernels.hpp"
#include "kernel/core/sundials_stepper.hpp"

#include <cvodes/cvodes.h>
#include <cvodes/cvodes_ls.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <vector>

namespace thermnet::detail {

/// What the sensitivity right-hand side needs beside the evaluator: the parameters, and dF/dT at
/// the last (t, y) it was evaluated at (the staggered corrector asks at the same point repeatedly).
struct SensitivityContext {
  ParameterDerivatives* d = nullptr;        // the parameters
  const SparsityPattern* pattern = nullptr; // of dF/dT
  std::vector<double> J;                    // dF/dT at (tJ, yJ), pattern order
  double tJ = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> yJ;
  std::vector<std::vector<double>> dF; // dF/dp_j at (tJ, yJ)
};

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

/// dS_j/dt = (dF/dT S_j + dF/dp_j - (F/C) dC/dp_j) / C for every parameter j.
int cv_sens_rhs(int ns, sunrealtype t, N_Vector y, N_Vector ydot, N_Vector* yS, N_Vector* ySdot,
                void* user_data, N_Vector, N_Vector) {
  SystemEvaluator& ev = evaluator(user_data);
  SensitivityContext& s = *ev.sensitivities;
  const int n = ev.size();
  const double tc = ev.clamp(t);
  const double* Y = NV_DATA_S(y);
  try {
    if (!(tc == s.tJ) || !std::equal(Y, Y + n, s.yJ.begin())) {
      s.tJ = std::numeric_limits<double>::quiet_NaN();
      ev.system().jacobian(tc, Y, s.J.data());
      for (int j = 0; j < ns; ++j)
        s.d->heat_balance(j, tc, Y, s.dF[static_cast<std::size_t>(j)].data());
      s.tJ = tc;
      std::copy(Y, Y + n, s.yJ.begin());
    }
    const double* f = NV_DATA_S(ydot);
    const double* inv_c = ev.inverse_capacities().data();
    const int* row = s.pattern->row_ptr.data();
    const int* col = s.pattern->col_idx.data();
    const double* J = s.J.data();
    for (int j = 0; j < ns; ++j) {
      const double* v = NV_DATA_S(yS[j]);
      double* out = NV_DATA_S(ySdot[j]);
      const double* dF = s.dF[static_cast<std::size_t>(j)].data();
      for (int i = 0; i < n; ++i) {
        double sum = dF[i];
        for (int k = row[i]; k < row[i + 1]; ++k)
          sum += J[k] * v[col[k]];
        out[i] = sum;
      }
      if (const std::vector<double>& dC = s.d->capacities(j); !dC.empty())
        for (int i = 0; i < n; ++i)
          out[i] -= f[i] * dC[static_cast<std::size_t>(i)];
      for (int i = 0; i < n; ++i) {
        out[i] *= inv_c[i];
        if (!std::isfinite(out[i])) return 1;
      }
    }
  } catch (...) {
    ev.pending = std::current_exception();
    return -1;
  }
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

/// Owns an array of N_Vectors.
struct VectorArray {
  N_Vector* v = nullptr;
  int count = 0;
  VectorArray() = default;
  VectorArray(const VectorArray&) = delete;
  VectorArray& operator=(const VectorArray&) = delete;
  ~VectorArray() {
    if (v) N_VDestroyVectorArray(v, count);
  }
};

class CvodeStepper final : public SundialsStepper {
public:
  CvodeStepper(SystemEvaluator& ev, LinearSolverKind kind, const SolverOptions& opt, double t0,
               const double* T0, double stop, SensitivityStart sens)
      : SundialsStepper(kCvode, "CVODE", ev, kind), opt_(opt), t_restart_(t0) {
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

    if (sens.derivatives && sens.derivatives->count() > 0) init_sensitivities(sens);

    if (!roots_.empty()) {
      chk_.call(Api::cvode, "CVodeRootInit", CVodeRootInit, mem, static_cast<int>(roots_.size()),
                cv_events);
      chk_.call(Api::cvode, "CVodeSetNoInactiveRootWarn", CVodeSetNoInactiveRootWarn, mem);
    }
    chk_.call(Api::cvode, "CVodeSetStopTime", CVodeSetStopTime, mem, stop);
  }

  ~CvodeStepper() override {
    if (ev_.sensitivities == &sens_) ev_.sensitivities = nullptr;
  }

  void restart(double t, double stop) override {
    accumulate();
    accumulate_sensitivities();
    // the sensitivities at t, continuous across the restart (t is not moved by the parameters)
    if (yS_.v) chk_.call(Api::cvode, "CVodeGetSensDky", CVodeGetSensDky, mem_.get(), t, 0, yS_.v);
    t_restart_ = t;
    stepped_ = false;
    ev_.set_window(t, stop);
    chk_.call(Api::cvode, "CVodeReInit", CVodeReInit, mem_.get(), t, y_.get());
    if (yS_.v)
      chk_.call(Api::cvode, "CVodeSensReInit", CVodeSensReInit, mem_.get(), CV_STAGGERED, yS_.v);
    chk_.call(Api::cvode, "CVodeSetStopTime", CVodeSetStopTime, mem_.get(), stop);
  }

  void collect(SolverStats& stats) override {
    accumulate_sensitivities();
    SundialsStepper::collect(stats);
    stats.sensitivities = yS_.count;
    stats.sens_rhs_evals += sens_acc_.sens_rhs_evals;
    stats.sens_nonlinear_iters += sens_acc_.sens_nonlinear_iters;
    stats.sens_nonlinear_fails += sens_acc_.sens_nonlinear_fails;
    sens_acc_ = SolverStats{};
  }

  void interpolate_sensitivities(double t, std::vector<std::vector<double>>& out) override {
    if (!out_S_.v) return;
    out.resize(static_cast<std::size_t>(out_S_.count));
    if (!stepped_) { // no step since the (re)start: the start values (dense output has none yet)
      for (int j = 0; j < yS_.count; ++j) {
        const double* s = NV_DATA_S(yS_.v[j]);
        out[static_cast<std::size_t>(j)].assign(s, s + n_);
      }
      return;
    }
    for (int j = 0; j < out_S_.count; ++j) {
      out[static_cast<std::size_t>(j)].resize(static_cast<std::size_t>(n_));
      N_VSetArrayPointer(out[static_cast<std::size_t>(j)].data(), out_S_.v[j]);
    }
    chk_.call(Api::cvode, "CVodeGetSensDky", CVodeGetSensDky, mem_.get(), t, 0, out_S_.v);
  }

  StepResult step(double stop, double& t) override {
    started_ = true;
    stepped_ = true;
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

  /// Adds the sensitivities' counters of the current segment (a re-initialisation resets them).
  void accumulate_sensitivities() {
    if (!yS_.v) return;
    long nfS = 0, nfevalsS = 0, netfS = 0, nlinsetupsS = 0, nniS = 0, ncfnS = 0;
    CVodeGetSensStats(mem_.get(), &nfS, &nfevalsS, &netfS, &nlinsetupsS);
    CVodeGetSensNonlinSolvStats(mem_.get(), &nniS, &ncfnS);
    sens_acc_.sens_rhs_evals += nfS;
    sens_acc_.sens_nonlinear_iters += nniS;
    sens_acc_.sens_nonlinear_fails += ncfnS;
  }

  /// Forward sensitivities: the staggered corrector (the state's Newton iterations first, with
  /// the same Newton matrix for the sensitivities), tolerances from the state's scaled by each
  /// parameter's typical size, and steps chosen by the state's error alone (the state is then
  /// the same as without sensitivities).
  void init_sensitivities(const SensitivityStart& start) {
    ParameterDerivatives& d = *start.derivatives;
    const int ns = d.count();
    sens_.d = &d;
    sens_.pattern = &ev_.system().jacobian_pattern();
    sens_.J.assign(static_cast<std::size_t>(sens_.pattern->nnz()), 0.0);
    sens_.yJ.assign(static_cast<std::size_t>(n_), 0.0);
    sens_.dF.assign(static_cast<std::size_t>(ns),
                    std::vector<double>(static_cast<std::size_t>(n_)));
    ev_.sensitivities = &sens_;
    yS_.v = chk_.created(N_VCloneVectorArray(ns, y_.get()), "N_VCloneVectorArray");
    yS_.count = ns;
    out_S_.v = chk_.created(N_VCloneEmptyVectorArray(ns, y_.get()), "N_VCloneEmptyVectorArray");
    out_S_.count = ns;
    std::vector<double> pbar(static_cast<std::size_t>(ns));
    for (int j = 0; j < ns; ++j) {
      const auto ju = static_cast<std::size_t>(j);
      double* s = NV_DATA_S(yS_.v[j]);
      if (start.S0 && ju < start.S0->size() &&
          (*start.S0)[ju].size() == static_cast<std::size_t>(n_))
        std::copy((*start.S0)[ju].begin(), (*start.S0)[ju].end(), s);
      else
        std::fill(s, s + n_, 0.0);
      const double scale = std::abs(d.scale(j));
      pbar[ju] = scale > 0.0 && std::isfinite(scale) ? scale : 1.0;
    }
    void* mem = mem_.get();
    chk_.call(Api::cvode, "CVodeSensInit", CVodeSensInit, mem, ns, CV_STAGGERED, cv_sens_rhs,
              yS_.v);
    chk_.call(Api::cvode, "CVodeSetSensParams", CVodeSetSensParams, mem, nullptr, pbar.data(),
              nullptr);
    const double rtol = std::max(opt_.rtol, opt_.sensitivity_tolerance);
    std::vector<double> atol(pbar.size());
    for (std::size_t j = 0; j < pbar.size(); ++j)
      atol[j] = std::max(opt_.atol, opt_.sensitivity_tolerance) / pbar[j];
    chk_.call(Api::cvode, "CVodeSensSStolerances", CVodeSensSStolerances, mem, rtol, atol.data());
    chk_.call(Api::cvode, "CVodeSetSensErrCon", CVodeSetSensErrCon, mem, SUNFALSE);
  }

  const SolverOptions& opt_;
  sundials::CvodeMemory mem_;
  double t_restart_ = 0.0;
  bool stepped_ = false; // a step was taken since the last (re)start
  SensitivityContext sens_;
  VectorArray yS_;       // the sensitivities (initial values, then the restart values)
  VectorArray out_S_;    // views of the caller's buffers for dense output
  SolverStats sens_acc_; // the sensitivities' counters of the finished segments
};

} // namespace

std::unique_ptr<TransientStepper> make_cvode_stepper(SystemEvaluator& ev, LinearSolverKind kind,
                                                     const SolverOptions& opt, double t0,
                                                     const double* T0, double stop,
                                                     SensitivityStart sens) {
  return std::make_unique<CvodeStepper>(ev, kind, opt, t0, T0, stop, sens);
}

} // namespace thermnet::detail
