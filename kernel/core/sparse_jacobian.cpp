#include "kernel/core/sparse_jacobian.hpp"

#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace thermnet::detail {

namespace {

/// The value of M at stored entry p of row i with diagonal position d.
inline double entry(const Combination& c, const double* v, int i, int p, int d) {
  double m = c.alpha * v[p];
  if (c.row_scale != nullptr) m *= c.row_scale[i];
  if (p == d) m += c.diag_scale * (c.diag != nullptr ? c.diag[i] : 1.0);
  return m;
}

} // namespace

SparseJacobian::SparseJacobian(const SparsityPattern& p) : n_(p.n) {
  const auto fail = [](const std::string& why) {
    throw std::invalid_argument("invalid Jacobian pattern: " + why);
  };
  if (p.n < 0) fail("negative size");
  if (p.row_ptr.size() != static_cast<std::size_t>(p.n) + 1)
    fail(fmt::format("row_ptr has {} entries for {} rows", p.row_ptr.size(), p.n));
  if (p.row_ptr.front() != 0 || p.row_ptr.back() != static_cast<int>(p.col_idx.size()))
    fail("row_ptr does not span col_idx");
  row_ptr_ = p.row_ptr;
  col_ = p.col_idx;
  diag_.assign(static_cast<std::size_t>(n_), -1);
  for (int i = 0; i < n_; ++i) {
    if (row_ptr_[i + 1] < row_ptr_[i]) fail(fmt::format("row {} has a negative length", i));
    for (int q = row_ptr_[i]; q < row_ptr_[i + 1]; ++q) {
      const int j = col_[q];
      if (j < 0 || j >= n_) fail(fmt::format("column {} out of range in row {}", j, i));
      if (q > row_ptr_[i] && col_[q - 1] >= j)
        fail(fmt::format("columns of row {} are not sorted and unique", i));
      if (j == i) diag_[i] = q;
    }
    if (diag_[i] < 0) fail(fmt::format("row {} has no diagonal entry", i));
  }
  row_ptr_s_.assign(row_ptr_.begin(), row_ptr_.end());
  col_s_.assign(col_.begin(), col_.end());
  values_.assign(col_.size(), 0.0);
  lu_.assign(col_.size(), 0.0);
  inv_pivot_.assign(static_cast<std::size_t>(n_), 0.0);
  work_.assign(static_cast<std::size_t>(n_), -1);
}

void SparseJacobian::fill_dense(SUNMatrix A, const Combination& c) const {
  double* data = SM_DATA_D(A);
  const std::size_t n = static_cast<std::size_t>(n_);
  std::fill(data, data + n * n, 0.0);
  const double* v = values_.data();
  for (int i = 0; i < n_; ++i) {
    const int d = diag_[i];
    for (int p = row_ptr_[i]; p < row_ptr_[i + 1]; ++p)
      data[static_cast<std::size_t>(col_[p]) * n + static_cast<std::size_t>(i)] =
          entry(c, v, i, p, d); // column-major
  }
}

void SparseJacobian::copy_pattern(SUNMatrix A) const {
  std::memcpy(SM_INDEXPTRS_S(A), row_ptr_s_.data(), row_ptr_s_.size() * sizeof(sunindextype));
  std::memcpy(SM_INDEXVALS_S(A), col_s_.data(), col_s_.size() * sizeof(sunindextype));
}

void SparseJacobian::fill_sparse_values(SUNMatrix A, const Combination& c) const {
  double* data = SM_DATA_S(A);
  const double* v = values_.data();
  for (int i = 0; i < n_; ++i) {
    const int d = diag_[i];
    for (int p = row_ptr_[i]; p < row_ptr_[i + 1]; ++p)
      data[p] = entry(c, v, i, p, d);
  }
}

void SparseJacobian::multiply(const Combination& c, const double* x, double* out) const {
  const double* v = values_.data();
  for (int i = 0; i < n_; ++i) {
    double s = 0.0;
    for (int p = row_ptr_[i]; p < row_ptr_[i + 1]; ++p)
      s += v[p] * x[col_[p]];
    s *= c.alpha;
    if (c.row_scale != nullptr) s *= c.row_scale[i];
    s += c.diag_scale * (c.diag != nullptr ? c.diag[i] : 1.0) * x[i];
    out[i] = s;
  }
}

bool SparseJacobian::factor_ilu(const Combination& c) {
  ++ilu_factorizations_;
  const double* v = values_.data();
  for (int i = 0; i < n_; ++i) {
    const int d = diag_[i];
    for (int p = row_ptr_[i]; p < row_ptr_[i + 1]; ++p)
      lu_[p] = entry(c, v, i, p, d);
  }
  // ILU(0), IKJ variant: for each row i, eliminate with the rows k < i of its pattern, keeping
  // only fill that falls on row i's own pattern. work_ maps a column to its position in row i.
  for (int i = 0; i < n_; ++i) {
    const int begin = row_ptr_[i];
    const int end = row_ptr_[i + 1];
    for (int p = begin; p < end; ++p)
      work_[col_[p]] = p;
    for (int p = begin; p < diag_[i]; ++p) {
      const int k = col_[p];
      const double m = lu_[p] * inv_pivot_[k];
      lu_[p] = m;
      for (int q = diag_[k] + 1; q < row_ptr_[k + 1]; ++q) {
        const int w = work_[col_[q]];
        if (w >= 0) lu_[w] -= m * lu_[q];
      }
    }
    for (int p = begin; p < end; ++p)
      work_[col_[p]] = -1;
    const double pivot = lu_[diag_[i]];
    if (!(std::abs(pivot) > 0.0) || !std::isfinite(pivot)) return false;
    inv_pivot_[i] = 1.0 / pivot;
  }
  return true;
}

void SparseJacobian::solve_ilu(const double* r, double* z) const {
  // The neighbour just solved (column i -/+ 1, common in networks numbered along their
  // couplings) is taken from a register rather than reloaded: the sweeps are latency bound.
  double prev = 0.0;
  for (int i = 0; i < n_; ++i) { // L (unit diagonal)
    double s = r[i];
    int end = diag_[i];
    if (end > row_ptr_[i] && col_[end - 1] == i - 1) s -= lu_[--end] * prev;
    for (int p = row_ptr_[i]; p < end; ++p)
      s -= lu_[p] * z[col_[p]];
    z[i] = prev = s;
  }
  for (int i = n_ - 1; i >= 0; --i) { // U
    double s = z[i];
    int begin = diag_[i] + 1;
    if (begin < row_ptr_[i + 1] && col_[begin] == i + 1) s -= lu_[begin++] * prev;
    for (int p = begin; p < row_ptr_[i + 1]; ++p)
      s -= lu_[p] * z[col_[p]];
    z[i] = prev = s * inv_pivot_[i];
  }
}

} // namespace thermnet::detail
