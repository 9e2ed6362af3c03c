#include "kernel/core/sundials_check.hpp"

#include <cvodes/cvodes.h>
#include <cvodes/cvodes_ls.h>
#include <ida/ida.h>
#include <ida/ida_ls.h>
#include <kinsol/kinsol.h>
#include <kinsol/kinsol_ls.h>

#include <fmt/format.h>

#include <cstdlib>

namespace thermnet::sundials {

Context::Context() {
  if (SUNContext_Create(nullptr, &ctx_) != 0 || ctx_ == nullptr)
    throw SolverError("SUNDIALS could not create its context (SUNContext_Create failed).",
                      "SUNContext_Create", -1, 0.0, {});
}

Context::~Context() {
  if (ctx_ != nullptr) SUNContext_Free(&ctx_);
}

void NVectorDeleter::operator()(N_Vector v) const noexcept {
  N_VDestroy(v);
}
void MatrixDeleter::operator()(SUNMatrix m) const noexcept {
  SUNMatDestroy(m);
}
void LinearSolverDeleter::operator()(SUNLinearSolver s) const noexcept {
  SUNLinSolFree(s);
}
void CvodeDeleter::operator()(void* mem) const noexcept {
  CVodeFree(&mem);
}
void IdaDeleter::operator()(void* mem) const noexcept {
  IDAFree(&mem);
}
void KinsolDeleter::operator()(void* mem) const noexcept {
  KINFree(&mem);
}

namespace {

/// Copies and frees a name returned by the SUNDIALS *GetReturnFlagName functions (malloc'd).
std::string take_name(char* name) {
  if (name == nullptr) return "unknown flag";
  std::string s(name);
  std::free(name);
  return s;
}

std::string sunls_name(int flag) {
  switch (flag) {
  case SUNLS_MEM_NULL:
    return "SUNLS_MEM_NULL";
  case SUNLS_ILL_INPUT:
    return "SUNLS_ILL_INPUT";
  case SUNLS_MEM_FAIL:
    return "SUNLS_MEM_FAIL";
  case SUNLS_ATIMES_NULL:
    return "SUNLS_ATIMES_NULL";
  case SUNLS_ATIMES_FAIL_UNREC:
    return "SUNLS_ATIMES_FAIL_UNREC";
  case SUNLS_PSET_FAIL_UNREC:
    return "SUNLS_PSET_FAIL_UNREC";
  case SUNLS_PSOLVE_NULL:
    return "SUNLS_PSOLVE_NULL";
  case SUNLS_PSOLVE_FAIL_UNREC:
    return "SUNLS_PSOLVE_FAIL_UNREC";
  case SUNLS_PACKAGE_FAIL_UNREC:
    return "SUNLS_PACKAGE_FAIL_UNREC";
  case SUNLS_GS_FAIL:
    return "SUNLS_GS_FAIL";
  case SUNLS_QRSOL_FAIL:
    return "SUNLS_QRSOL_FAIL";
  case SUNLS_VECTOROP_ERR:
    return "SUNLS_VECTOROP_ERR";
  default:
    return fmt::format("SUNLS flag {}", flag);
  }
}

std::string cvode_description(int flag) {
  switch (flag) {
  case CV_TOO_MUCH_WORK:
    return "the maximum number of internal steps was taken";
  case CV_TOO_MUCH_ACC:
    return "the requested accuracy is beyond double precision";
  case CV_ERR_FAILURE:
    return "the local error test failed repeatedly";
  case CV_CONV_FAILURE:
    return "the corrector convergence failed repeatedly";
  case CV_LINIT_FAIL:
    return "the linear solver could not be initialised";
  case CV_LSETUP_FAIL:
    return "the Jacobian could not be evaluated or factorised";
  case CV_LSOLVE_FAIL:
    return "the linear solve failed";
  case CV_RHSFUNC_FAIL:
    return "the heat balance failed unrecoverably";
  case CV_FIRST_RHSFUNC_ERR:
    return "the heat balance failed at the initial state";
  case CV_REPTD_RHSFUNC_ERR:
    return "the heat balance failed repeatedly";
  case CV_UNREC_RHSFUNC_ERR:
    return "the heat balance failed and the step could not be recovered";
  case CV_RTFUNC_FAIL:
    return "an event function failed";
  case CV_TOO_CLOSE:
    return "the end time is too close to the start time";
  case CV_ILL_INPUT:
    return "an input was invalid";
  case CV_MEM_FAIL:
    return "memory could not be allocated";
  case CV_BAD_T:
    return "a time outside the last step was requested";
  default:
    return "the integrator reported an error";
  }
}

std::string ida_description(int flag) {
  switch (flag) {
  case IDA_TOO_MUCH_WORK:
    return "the maximum number of internal steps was taken";
  case IDA_TOO_MUCH_ACC:
    return "the requested accuracy is beyond double precision";
  case IDA_ERR_FAIL:
    return "the local error test failed repeatedly";
  case IDA_CONV_FAIL:
    return "the corrector convergence failed repeatedly";
  case IDA_LINIT_FAIL:
    return "the linear solver could not be initialised";
  case IDA_LSETUP_FAIL:
    return "the Jacobian could not be evaluated or factorised";
  case IDA_LSOLVE_FAIL:
    return "the linear solve failed";
  case IDA_RES_FAIL:
    return "the heat balance failed unrecoverably";
  case IDA_REP_RES_ERR:
    return "the heat balance failed repeatedly";
  case IDA_RTFUNC_FAIL:
    return "an event function failed";
  case IDA_FIRST_RES_FAIL:
    return "the heat balance failed at the initial state";
  case IDA_LINESEARCH_FAIL:
    return "no consistent temperatures of the arithmetic nodes were found (line search failed)";
  case IDA_NO_RECOVERY:
    return "no consistent temperatures of the arithmetic nodes were found (the Newton "
           "iteration could not recover)";
  case IDA_CONSTR_FAIL:
    return "the temperature constraints could not be met";
  case IDA_ILL_INPUT:
    return "an input was invalid";
  case IDA_MEM_FAIL:
    return "memory could not be allocated";
  case IDA_BAD_T:
    return "a time outside the last step was requested";
  default:
    return "the integrator reported an error";
  }
}

std::string kinsol_description(int flag) {
  switch (flag) {
  case KIN_LINESEARCH_NONCONV:
    return "the line search could not find an iterate that sufficiently decreases the residual";
  case KIN_MAXITER_REACHED:
    return "the maximum number of Newton iterations was reached";
  case KIN_MXNEWT_5X_EXCEEDED:
    return "five consecutive Newton steps reached the maximum step length (the solution may be "
           "unbounded)";
  case KIN_LINESEARCH_BCFAIL:
    return "the line search failed the beta condition repeatedly";
  case KIN_LINSOLV_NO_RECOVERY:
  case KIN_LSETUP_FAIL:
  case KIN_LSOLVE_FAIL:
    return "the Jacobian is singular or could not be factorised (a node may lack a conductive "
           "path to a fixed temperature)";
  case KIN_SYSFUNC_FAIL:
    return "the heat balance failed unrecoverably";
  case KIN_FIRST_SYSFUNC_ERR:
    return "the heat balance failed at the initial guess";
  case KIN_REPTD_SYSFUNC_ERR:
    return "the heat balance failed repeatedly";
  case KIN_STEP_LT_STPTOL:
    return "the Newton steps became negligible while the residual was still large";
  case KIN_ILL_INPUT:
    return "an input was invalid";
  case KIN_MEM_FAIL:
    return "memory could not be allocated";
  default:
    return "the nonlinear solver reported an error";
  }
}

} // namespace

std::string flag_name(Api api, int flag) {
  switch (api) {
  case Api::cvode:
    return take_name(CVodeGetReturnFlagName(flag));
  case Api::cvode_ls:
    return take_name(CVodeGetLinReturnFlagName(flag));
  case Api::ida:
    return take_name(IDAGetReturnFlagName(flag));
  case Api::ida_ls:
    return take_name(IDAGetLinReturnFlagName(flag));
  case Api::kinsol:
    return take_name(KINGetReturnFlagName(flag));
  case Api::kinsol_ls:
    return take_name(KINGetLinReturnFlagName(flag));
  case Api::sunlinsol:
    return sunls_name(flag);
  }
  return "unknown flag";
}

std::string flag_description(Api api, int flag) {
  switch (api) {
  case Api::cvode:
    return cvode_description(flag);
  case Api::ida:
    return ida_description(flag);
  case Api::kinsol:
    return kinsol_description(flag);
  case Api::cvode_ls:
  case Api::ida_ls:
  case Api::kinsol_ls:
    return "the linear solver interface rejected the call";
  case Api::sunlinsol:
    return "the linear solver reported an error";
  }
  return "SUNDIALS reported an error";
}

int Checker::check(Api api, int flag, const char* call) {
  if (flag >= 0) return flag;
  fail(call, flag, flag_name(api, flag), flag_description(api, flag));
}

void Checker::fail(const char* call, int flag, const std::string& name,
                   const std::string& description) {
  if (pending != nullptr && *pending) {
    std::exception_ptr e = *pending;
    *pending = nullptr;
    std::rethrow_exception(e);
  }
  FailureReport d;
  if (describe_failure) {
    try {
      d = describe_failure();
    } catch (...) {
      d = FailureReport{};
    }
  }
  std::string what =
      steady
          ? fmt::format("{} failed to find the steady state (inputs at t = {:.10g} s): {} ({})",
                        module_, d.time, description, name)
          : fmt::format("{} failed at t = {:.10g} s: {} ({})", module_, d.time, description, name);
  if (!d.note.empty()) what += fmt::format("; {}", d.note);
  if (!d.worst.empty() && !d.worst_label.empty())
    what += fmt::format("; {} {}", d.worst_label, fmt::join(d.worst, ", "));
  what += ".";
  if (!last_message_.empty()) what += fmt::format(" [{}: {}]", call, last_message_);
  throw SolverError(what, call, flag, d.time, std::move(d.worst));
}

void Checker::handler(int error_code, const char* /*module*/, const char* /*function*/, char* msg,
                      void* self) {
  // Warnings (error_code > 0, e.g. "t + h = t") are silenced; errors are kept for the exception.
  if (error_code >= 0 || self == nullptr || msg == nullptr) return;
  static_cast<Checker*>(self)->last_message_ = msg;
}

} // namespace thermnet::sundials
