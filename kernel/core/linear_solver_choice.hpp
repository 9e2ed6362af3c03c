#pragma once
/// The choice of linear solver for a solve: resolves `automatic`, names the choice for stats, and
/// creates the SUNDIALS matrix and linear solver objects for it.

#include "kernel/core/solver_types.hpp"
#include "kernel/core/sparse_jacobian.hpp"
#include "kernel/core/sundials_check.hpp"

namespace thermnet::detail {

/// Resolves `automatic` (dense up to `dense_threshold` unknowns, KLU up to `krylov_threshold`,
/// Krylov above); others pass
/// through.
LinearSolverKind resolve_linear_solver(LinearSolverKind requested, int size, int dense_threshold,
                                       int krylov_threshold);

/// The name reported in SolverStats::linear_solver: "dense", "klu" or "spgmr".
const char* linear_solver_name(LinearSolverKind kind);

/// A matrix (null for the matrix-free SPGMR) and its linear solver.
struct LinearSystem {
  sundials::Matrix matrix; ///< SUNDenseMatrix, or SUNSparseMatrix (CSR) with the pattern in place
  sundials::LinearSolver solver; ///< SUNLinSol_Dense, SUNLinSol_KLU or SUNLinSol_SPGMR (left prec.)
};

/// Creates the matrix and linear solver of `kind` (not automatic) for the pattern of `jac`.
/// KLU keeps its symbolic analysis across integrator restarts (only values change).
LinearSystem make_linear_system(LinearSolverKind kind, const SparseJacobian& jac, N_Vector tmpl,
                                SUNContext ctx, sundials::Checker& chk);

} // namespace thermnet::detail
