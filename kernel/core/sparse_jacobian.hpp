#pragma once
/// The analytic Jacobian dF/dT on the system's fixed CSR pattern: fills SUNDIALS dense and sparse
/// matrices with the Newton matrix, multiplies vectors, and factors an ILU(0) preconditioner.

#include "kernel/core/thermal_system.hpp"

#include <sundials/sundials_matrix.h>
#include <sundials/sundials_types.h>

#include <vector>

namespace thermnet::detail {

/// The matrix M = alpha * diag(row_scale) * J + diag_scale * diag(diag), built from J = dF/dT.
/// A null row_scale means ones; a null diag means ones.
struct Combination {
  double alpha = 1.0;                ///< factor of J
  const double* row_scale = nullptr; ///< per-row factor of J (e.g. 1/C), or null
  double diag_scale = 0.0;           ///< factor of the added diagonal
  const double* diag = nullptr;      ///< added diagonal (e.g. C), or null for the identity
};

/// dF/dT values on a pattern copied once, plus the operations the linear solvers need.
/// Nothing here allocates after construction.
class SparseJacobian {
public:
  /// Copies and validates the pattern (square, sorted rows, in-range columns, diagonal present);
  /// throws std::invalid_argument otherwise.
  explicit SparseJacobian(const SparsityPattern& pattern);

  /// Number of rows.
  int size() const { return n_; }
  /// Number of stored entries.
  int nnz() const { return static_cast<int>(col_.size()); }
  /// Values of dF/dT in pattern order (filled by ThermalSystem::jacobian).
  double* values() { return values_.data(); }
  /// Values of dF/dT in pattern order.
  const double* values() const { return values_.data(); }
  /// Index of row i's diagonal entry.
  int diagonal_position(int i) const { return diag_[static_cast<std::size_t>(i)]; }

  /// Writes M into a SUNDIALS dense matrix (all n*n entries).
  void fill_dense(SUNMatrix A, const Combination& c) const;
  /// Writes the CSR index arrays into a SUNDIALS sparse CSR matrix of nnz() entries.
  void copy_pattern(SUNMatrix A) const;
  /// Writes M's values into a SUNDIALS sparse CSR matrix whose pattern is already in place.
  void fill_sparse_values(SUNMatrix A, const Combination& c) const;
  /// out = M v.
  void multiply(const Combination& c, const double* v, double* out) const;
  /// Forms M and factors it in place by ILU(0); false if a pivot vanishes.
  bool factor_ilu(const Combination& c);
  /// Number of ILU(0) factorisations made so far (preconditioner setups).
  long ilu_factorizations() const { return ilu_factorizations_; }
  /// Solves (L U) z = r with the last ILU(0) factors.
  void solve_ilu(const double* r, double* z) const;
  /// Diagonal of dF/dT (in W/K), one per row.
  double diagonal(int i) const { return values_[static_cast<std::size_t>(diag_[i])]; }

private:
  int n_ = 0;
  std::vector<int> row_ptr_;
  std::vector<int> col_;
  std::vector<int> diag_;
  std::vector<sunindextype> row_ptr_s_;
  std::vector<sunindextype> col_s_;
  std::vector<double> values_;
  std::vector<double> lu_;
  std::vector<double> inv_pivot_;
  std::vector<int> work_;
  long ilu_factorizations_ = 0;
};

} // namespace thermnet::detail
