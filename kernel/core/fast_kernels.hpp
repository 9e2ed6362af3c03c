#pragma once
/// Optimised kernels plugged into SUNDIALS objects through their operation tables.
///
/// Debian's libsundials 6.4.1 is compiled without optimisation (-O0), so its serial vector
/// operations and dense LU dominate small and large solves alike. SUNDIALS objects carry
/// per-object operation tables; these functions point them at equivalent kernels compiled with
/// the project's flags. Semantics (including aliasing of inputs and outputs) are unchanged.

#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_nvector.h>

namespace thermnet::detail {

/// Replaces the arithmetic operations of a serial N_Vector (and of every later clone of it).
void accelerate_vector(N_Vector v);

/// Replaces setup (LU with partial pivoting) and solve of a SUNLinSol_Dense solver.
void accelerate_dense_solver(SUNLinearSolver s);

} // namespace thermnet::detail
