#include "kernel/core/sundials_stepper.hpp"

#include "kernel/core/fast_kernels.hpp"

#include <nvector/nvector_serial.h>

#include <algorithm>

namespace thermnet::detail {

SundialsStepper::SundialsStepper(const IntegratorApi& api, const char* module, SystemEvaluator& ev,
                                 LinearSolverKind kind)
    : ev_(ev), kind_(kind), n_(ev.size()), chk_(module), api_(api) {
  chk_.pending = &ev_.pending;
  chk_.describe_failure = [this] { return failure_report(); };
  roots_.assign(static_cast<std::size_t>(ev_.system().event_count()), 0);
}

void SundialsStepper::create_state(const double* T0) {
  const SUNContext ctx = ctx_.get();
  y_.reset(chk_.created(N_VNew_Serial(n_, ctx), "N_VNew_Serial"));
  out_.reset(chk_.created(N_VNewEmpty_Serial(n_, ctx), "N_VNewEmpty_Serial"));
  accelerate_vector(y_.get()); // before the integrator and the solvers clone it
  accelerate_vector(out_.get());
  std::copy(T0, T0 + n_, NV_DATA_S(y_.get()));
}

void SundialsStepper::interpolate(double t, double* out) {
  N_VSetArrayPointer(out, out_.get());
  chk_.call(api_.api, api_.dky_name, api_.dky, memory(), t, 0, out_.get());
}

double SundialsStepper::current_time() {
  sunrealtype t = 0.0;
  chk_.call(api_.api, "GetCurrentTime", api_.current_time, memory(), &t);
  return t;
}

long SundialsStepper::steps() {
  long nst = 0;
  api_.num_steps(memory(), &nst);
  return acc_.steps + nst;
}

void SundialsStepper::collect(SolverStats& stats) {
  accumulate();
  stats.integrator = api_.name;
  stats.linear_solver = linear_solver_name(kind_);
  stats.steps += acc_.steps;
  stats.linear_setups += acc_.linear_setups;
  stats.nonlinear_iters += acc_.nonlinear_iters;
  stats.nonlinear_fails += acc_.nonlinear_fails;
  stats.linear_iters += acc_.linear_iters;
  stats.error_test_fails += acc_.error_test_fails;
  stats.rhs_evals += ev_.rhs_evals;
  stats.jac_evals += ev_.jac_evals;
  stats.prec_setups += ev_.jacobian_storage().ilu_factorizations();
  acc_ = SolverStats{};
}

void SundialsStepper::accumulate() {
  void* mem = memory();
  long nst = 0, nsetups = 0, netf = 0, nni = 0, ncfn = 0;
  api_.num_steps(mem, &nst);
  api_.num_lin_solv_setups(mem, &nsetups);
  api_.num_err_test_fails(mem, &netf);
  api_.nonlin_solv_stats(mem, &nni, &ncfn);
  acc_.steps += nst;
  acc_.linear_setups += nsetups;
  acc_.error_test_fails += netf;
  acc_.nonlinear_iters += nni;
  acc_.nonlinear_fails += ncfn;
  if (kind_ == LinearSolverKind::krylov) {
    long nli = 0;
    api_.num_lin_iters(mem, &nli);
    acc_.linear_iters += nli;
  }
}

StepResult SundialsStepper::outcome(int flag) {
  if (flag == api_.root_return) {
    chk_.call(api_.api, api_.root_info_name, api_.root_info, memory(), roots_.data());
    return StepResult::root_found;
  }
  if (flag == api_.tstop_return) return StepResult::stop_reached;
  return StepResult::advanced;
}

void SundialsStepper::explain_start_failure(sundials::FailureReport& /*d*/) const {}

sundials::FailureReport SundialsStepper::failure_report() {
  sundials::FailureReport d;
  void* mem = memory();
  api_.current_time(mem, &d.time);
  d.note = ev_.describe_nonfinite();
  if (ev_.nonfinite().seen) d.worst.push_back(ev_.name(ev_.nonfinite().index));
  if (!started_) {
    explain_start_failure(d);
    return d;
  }
  std::vector<double> w(static_cast<std::size_t>(n_)), e(static_cast<std::size_t>(n_));
  sundials::NVector wv(N_VMake_Serial(n_, w.data(), ctx_.get()));
  sundials::NVector ev_vec(N_VMake_Serial(n_, e.data(), ctx_.get()));
  if (wv && ev_vec && api_.err_weights(mem, wv.get()) == api_.success &&
      api_.est_local_errors(mem, ev_vec.get()) == api_.success) {
    for (std::size_t i = 0; i < w.size(); ++i)
      e[i] *= w[i];
    for (std::string& name : ev_.worst_unknowns(e.data()))
      if (d.worst.empty() || d.worst.front() != name) d.worst.push_back(std::move(name));
  }
  d.worst_label = "largest local errors at nodes";
  return d;
}

} // namespace thermnet::detail
