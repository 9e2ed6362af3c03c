#pragma once
/// SUNDIALS resource owners (RAII) and the one checked-call helper that turns SUNDIALS failures
/// into SolverError naming the call, the flag, the simulation time and the worst unknowns.

#include "kernel/core/solver_types.hpp"

#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nvector.h>

#include <exception>
#include <functional>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace thermnet::sundials {

/// Owns a SUNContext (SUNDIALS 6: one per solve, created with SUNContext_Create(NULL, ...)).
class Context {
public:
  /// Creates the context; throws SolverError if SUNDIALS cannot.
  Context();
  /// Frees the context (after every object created with it).
  ~Context();
  Context(const Context&) = delete;            ///< not copyable
  Context& operator=(const Context&) = delete; ///< not copyable
  /// The raw context for SUNDIALS constructors.
  SUNContext get() const { return ctx_; }

private:
  SUNContext ctx_ = nullptr;
};

/// Destroys an N_Vector.
struct NVectorDeleter {
  /// Calls N_VDestroy.
  void operator()(N_Vector v) const noexcept;
};
/// Destroys a SUNMatrix.
struct MatrixDeleter {
  /// Calls SUNMatDestroy.
  void operator()(SUNMatrix m) const noexcept;
};
/// Frees a SUNLinearSolver.
struct LinearSolverDeleter {
  /// Calls SUNLinSolFree.
  void operator()(SUNLinearSolver s) const noexcept;
};
/// Frees CVODE memory.
struct CvodeDeleter {
  /// Calls CVodeFree.
  void operator()(void* mem) const noexcept;
};
/// Frees IDA memory.
struct IdaDeleter {
  /// Calls IDAFree.
  void operator()(void* mem) const noexcept;
};
/// Frees KINSOL memory.
struct KinsolDeleter {
  /// Calls KINFree.
  void operator()(void* mem) const noexcept;
};

/// An owned N_Vector.
using NVector = std::unique_ptr<std::remove_pointer_t<N_Vector>, NVectorDeleter>;
/// An owned SUNMatrix.
using Matrix = std::unique_ptr<std::remove_pointer_t<SUNMatrix>, MatrixDeleter>;
/// An owned SUNLinearSolver.
using LinearSolver = std::unique_ptr<std::remove_pointer_t<SUNLinearSolver>, LinearSolverDeleter>;
/// Owned CVODE memory.
using CvodeMemory = std::unique_ptr<void, CvodeDeleter>;
/// Owned IDA memory.
using IdaMemory = std::unique_ptr<void, IdaDeleter>;
/// Owned KINSOL memory.
using KinsolMemory = std::unique_ptr<void, KinsolDeleter>;

/// Which SUNDIALS interface a return flag belongs to (selects its name and description).
enum class Api {
  cvode,     ///< CVODE integrator functions (CV_*)
  cvode_ls,  ///< CVODE linear solver interface (CVLS_*)
  ida,       ///< IDA integrator functions (IDA_*)
  ida_ls,    ///< IDA linear solver interface (IDALS_*)
  kinsol,    ///< KINSOL functions (KIN_*)
  kinsol_ls, ///< KINSOL linear solver interface (KINLS_*)
  sunlinsol  ///< SUNLinearSolver / SUNMatrix functions (SUNLS_*)
};

/// The symbolic name of a flag, e.g. "CV_CONV_FAILURE".
std::string flag_name(Api api, int flag);
/// A human description of a failure flag, e.g. "the corrector convergence failed repeatedly".
std::string flag_description(Api api, int flag);

/// What is known about a failure beyond the flag (gathered lazily, only when something fails).
struct FailureReport {
  double time = 0.0;              ///< simulation time reached, s
  std::vector<std::string> worst; ///< worst unknowns, worst first
  std::string worst_label;        ///< e.g. "largest local errors at nodes" (empty: not printed)
  std::string note;               ///< extra sentence fragment, e.g. a non-finite heat balance
};

/// Turns SUNDIALS return flags into SolverError. Every SUNDIALS return code goes through check().
///
/// Registered as the solver's error handler (handler()), it silences SUNDIALS' own printing to
/// stderr and keeps the last message for the exception instead.
class Checker {
public:
  /// A checker for one solver; `module` is "CVODE", "IDA" or "KINSOL".
  explicit Checker(std::string module) : module_(std::move(module)) {}

  /// Returns `flag` if it is not an error (>= 0); otherwise throws SolverError naming `call`.
  int check(Api api, int flag, const char* call);

  /// Calls `fn(args...)` and passes its return flag through check().
  template <typename Fn, typename... Args>
  int call(Api api, const char* name, Fn fn, Args&&... args) {
    return check(api, fn(std::forward<Args>(args)...), name);
  }

  /// Returns `object` if non-null; otherwise throws SolverError (a SUNDIALS constructor failed).
  template <typename P> P created(P object, const char* call) {
    if (object == nullptr)
      fail(call, -1, "NULL", "the object could not be created (out of memory?)");
    return object;
  }

  /// Throws SolverError for a failure of `call` with the given flag name and description.
  [[noreturn]] void fail(const char* call, int flag, const std::string& name,
                         const std::string& description);

  /// SUNDIALS error handler (CVErrHandlerFn/IDAErrHandlerFn/KINErrHandlerFn); `self` is a Checker.
  static void handler(int error_code, const char* module, const char* function, char* msg,
                      void* self);

  /// Gathers time and worst unknowns when a failure is reported (may be empty).
  std::function<FailureReport()> describe_failure;
  /// If set and holding an exception (thrown by a user callback), it is rethrown instead.
  std::exception_ptr* pending = nullptr;
  /// Subject of the message: "failed at t = ..." (transient) or "failed to find the steady state".
  bool steady = false;

private:
  std::string module_;
  std::string last_message_;
};

} // namespace thermnet::sundials
