#include "kernel/core/fast_kernels.hpp"

#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cmath>
#include <cstring>

// The dense kernels are compiled twice, for AVX2/FMA and for baseline x86-64; the loader picks
// one for the running CPU (GNU ifunc).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__)
#define TN_VECTOR_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define TN_VECTOR_CLONES
#endif

namespace thermnet::detail {

namespace {

using Index = sunindextype;

inline Index len(N_Vector v) {
  return NV_LENGTH_S(v);
}
inline double* dat(N_Vector v) {
  return NV_DATA_S(v);
}

// ---- elementwise operations (outputs may alias inputs: each z[i] depends on index i only) ----

void linear_sum(double a, N_Vector x, double b, N_Vector y, N_Vector z) {
  const Index n = len(x);
  const double* xd = dat(x);
  const double* yd = dat(y);
  double* zd = dat(z);
  if (a == 1.0 && b == 1.0) {
    for (Index i = 0; i < n; ++i)
      zd[i] = xd[i] + yd[i];
  } else if (a == 1.0 && b == -1.0) {
    for (Index i = 0; i < n; ++i)
      zd[i] = xd[i] - yd[i];
  } else if (a == -1.0 && b == 1.0) {
    for (Index i = 0; i < n; ++i)
      zd[i] = yd[i] - xd[i];
  } else if (a == 1.0) {
    for (Index i = 0; i < n; ++i)
      zd[i] = xd[i] + b * yd[i];
  } else if (b == 1.0) {
    for (Index i = 0; i < n; ++i)
      zd[i] = a * xd[i] + yd[i];
  } else {
    for (Index i = 0; i < n; ++i)
      zd[i] = a * xd[i] + b * yd[i];
  }
}

void constant(double c, N_Vector z) {
  std::fill(dat(z), dat(z) + len(z), c);
}

void prod(N_Vector x, N_Vector y, N_Vector z) {
  const Index n = len(x);
  const double* xd = dat(x);
  const double* yd = dat(y);
  double* zd = dat(z);
  for (Index i = 0; i < n; ++i)
    zd[i] = xd[i] * yd[i];
}

void divide(N_Vector x, N_Vector y, N_Vector z) {
  const Index n = len(x);
  const double* xd = dat(x);
  const double* yd = dat(y);
  double* zd = dat(z);
  for (Index i = 0; i < n; ++i)
    zd[i] = xd[i] / yd[i];
}

void scale(double c, N_Vector x, N_Vector z) {
  const Index n = len(x);
  const double* xd = dat(x);
  double* zd = dat(z);
  if (c == 1.0) {
    if (zd != xd) std::memcpy(zd, xd, static_cast<std::size_t>(n) * sizeof(double));
  } else if (c == -1.0) {
    for (Index i = 0; i < n; ++i)
      zd[i] = -xd[i];
  } else {
    for (Index i = 0; i < n; ++i)
      zd[i] = c * xd[i];
  }
}

void absolute(N_Vector x, N_Vector z) {
  const Index n = len(x);
  const double* xd = dat(x);
  double* zd = dat(z);
  for (Index i = 0; i < n; ++i)
    zd[i] = std::abs(xd[i]);
}

void inverse(N_Vector x, N_Vector z) {
  const Index n = len(x);
  const double* xd = dat(x);
  double* zd = dat(z);
  for (Index i = 0; i < n; ++i)
    zd[i] = 1.0 / xd[i];
}

void add_const(N_Vector x, double b, N_Vector z) {
  const Index n = len(x);
  const double* xd = dat(x);
  double* zd = dat(z);
  for (Index i = 0; i < n; ++i)
    zd[i] = xd[i] + b;
}

void compare(double c, N_Vector x, N_Vector z) {
  const Index n = len(x);
  const double* xd = dat(x);
  double* zd = dat(z);
  for (Index i = 0; i < n; ++i)
    zd[i] = std::abs(xd[i]) >= c ? 1.0 : 0.0;
}

// ---- reductions: four independent partial sums so the additions pipeline ----

double dot(N_Vector x, N_Vector y) {
  const Index n = len(x);
  const double* xd = dat(x);
  const double* yd = dat(y);
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  Index i = 0;
  for (; i + 4 <= n; i += 4) {
    s0 += xd[i] * yd[i];
    s1 += xd[i + 1] * yd[i + 1];
    s2 += xd[i + 2] * yd[i + 2];
    s3 += xd[i + 3] * yd[i + 3];
  }
  for (; i < n; ++i)
    s0 += xd[i] * yd[i];
  return (s0 + s1) + (s2 + s3);
}

double wsqr_sum(N_Vector x, N_Vector w) {
  const Index n = len(x);
  const double* xd = dat(x);
  const double* wd = dat(w);
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  Index i = 0;
  for (; i + 4 <= n; i += 4) {
    const double p0 = xd[i] * wd[i], p1 = xd[i + 1] * wd[i + 1];
    const double p2 = xd[i + 2] * wd[i + 2], p3 = xd[i + 3] * wd[i + 3];
    s0 += p0 * p0;
    s1 += p1 * p1;
    s2 += p2 * p2;
    s3 += p3 * p3;
  }
  for (; i < n; ++i) {
    const double p = xd[i] * wd[i];
    s0 += p * p;
  }
  return (s0 + s1) + (s2 + s3);
}

double wsqr_sum_mask(N_Vector x, N_Vector w, N_Vector id) {
  const Index n = len(x);
  const double* xd = dat(x);
  const double* wd = dat(w);
  const double* md = dat(id);
  double s = 0.0;
  for (Index i = 0; i < n; ++i) {
    const double p = md[i] > 0.0 ? xd[i] * wd[i] : 0.0;
    s += p * p;
  }
  return s;
}

double wrms_norm(N_Vector x, N_Vector w) {
  return std::sqrt(wsqr_sum(x, w) / static_cast<double>(len(x)));
}

double wrms_norm_mask(N_Vector x, N_Vector w, N_Vector id) {
  return std::sqrt(wsqr_sum_mask(x, w, id) / static_cast<double>(len(x)));
}

double wl2_norm(N_Vector x, N_Vector w) {
  return std::sqrt(wsqr_sum(x, w));
}

double max_norm(N_Vector x) {
  const Index n = len(x);
  const double* xd = dat(x);
  double m = 0.0;
  for (Index i = 0; i < n; ++i)
    m = std::max(m, std::abs(xd[i]));
  return m;
}

double min_value(N_Vector x) {
  const Index n = len(x);
  const double* xd = dat(x);
  double m = n > 0 ? xd[0] : 0.0;
  for (Index i = 1; i < n; ++i)
    m = std::min(m, xd[i]);
  return m;
}

double l1_norm(N_Vector x) {
  const Index n = len(x);
  const double* xd = dat(x);
  double s = 0.0;
  for (Index i = 0; i < n; ++i)
    s += std::abs(xd[i]);
  return s;
}

// ---- fused operations ----

/// z = sum_j c_j X_j; z may be any of the X_j.
int linear_combination(int nvec, double* c, N_Vector* X, N_Vector z) {
  if (nvec < 1) return -1;
  const Index n = len(z);
  double* zd = dat(z);
  bool z_in_tail = false;
  for (int j = 1; j < nvec; ++j)
    z_in_tail = z_in_tail || dat(X[j]) == zd;
  if (z_in_tail) { // rare: combine element by element
    for (Index i = 0; i < n; ++i) {
      double s = 0.0;
      for (int j = 0; j < nvec; ++j)
        s += c[j] * dat(X[j])[i];
      zd[i] = s;
    }
    return 0;
  }
  scale(c[0], X[0], z);
  for (int j = 1; j < nvec; ++j) {
    const double cj = c[j];
    const double* xd = dat(X[j]);
    for (Index i = 0; i < n; ++i)
      zd[i] += cj * xd[i];
  }
  return 0;
}

/// Z_j = a_j x + Y_j.
int scale_add_multi(int nvec, double* a, N_Vector x, N_Vector* Y, N_Vector* Z) {
  const Index n = len(x);
  const double* xd = dat(x);
  for (int j = 0; j < nvec; ++j) {
    const double aj = a[j];
    const double* yd = dat(Y[j]);
    double* zd = dat(Z[j]);
    for (Index i = 0; i < n; ++i)
      zd[i] = aj * xd[i] + yd[i];
  }
  return 0;
}

/// d_j = x . Y_j.
int dot_multi(int nvec, N_Vector x, N_Vector* Y, double* d) {
  for (int j = 0; j < nvec; ++j)
    d[j] = dot(x, Y[j]);
  return 0;
}

// ---- dense LU with partial pivoting (LAPACK getrf/getrs semantics, column-major) ----
//
// Only these two functions read the factored matrix (SUNDIALS refills it before every setup), so
// setup stores the reciprocal of each pivot on U's diagonal. The triangular solves handle four
// columns per pass over the remaining rows: a quarter of the dependent passes, and each pass reads
// x in the same aligned pairs the previous pass wrote (no store-to-load forwarding stalls).

TN_VECTOR_CLONES int dense_setup(SUNLinearSolver S, SUNMatrix A) {
  auto* content = static_cast<SUNLinearSolverContent_Dense>(S->content);
  const Index n = SM_COLUMNS_D(A);
  if (SM_ROWS_D(A) != n || content->N != n) {
    content->last_flag = SUNLS_ILL_INPUT;
    return SUNLS_ILL_INPUT;
  }
  double* a = SM_DATA_D(A);
  Index* piv = content->pivots;
  for (Index k = 0; k < n; ++k) {
    double* col_k = a + k * n;
    Index p = k;
    double big = std::abs(col_k[k]);
    for (Index i = k + 1; i < n; ++i)
      if (std::abs(col_k[i]) > big) {
        big = std::abs(col_k[i]);
        p = i;
      }
    piv[k] = p;
    if (col_k[p] == 0.0) {
      content->last_flag = k + 1;
      return SUNLS_LUFACT_FAIL;
    }
    if (p != k)
      for (Index j = 0; j < n; ++j)
        std::swap(a[j * n + k], a[j * n + p]);
    const double inv = 1.0 / col_k[k];
    col_k[k] = inv;
    for (Index i = k + 1; i < n; ++i)
      col_k[i] *= inv;
    for (Index j = k + 1; j < n; ++j) {
      double* col_j = a + j * n;
      const double m = col_j[k];
      if (m != 0.0)
        for (Index i = k + 1; i < n; ++i)
          col_j[i] -= m * col_k[i];
    }
  }
  content->last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

TN_VECTOR_CLONES int dense_solve(SUNLinearSolver S, SUNMatrix A, N_Vector x, N_Vector b,
                                 double /*tol*/) {
  auto* content = static_cast<SUNLinearSolverContent_Dense>(S->content);
  const Index n = SM_COLUMNS_D(A);
  const double* a = SM_DATA_D(A);
  const Index* piv = content->pivots;
  double* xd = dat(x);
  if (xd != dat(b)) std::memcpy(xd, dat(b), static_cast<std::size_t>(n) * sizeof(double));
  for (Index k = 0; k < n; ++k)
    if (piv[k] != k) std::swap(xd[k], xd[piv[k]]);
  const auto at = [a, n](Index i, Index j) { return a[j * n + i]; };

  // L y = P b, L unit lower triangular.
  Index k = 0;
  for (; k + 4 <= n; k += 4) {
    const double y0 = xd[k];
    const double y1 = xd[k + 1] - at(k + 1, k) * y0;
    const double y2 = xd[k + 2] - at(k + 2, k) * y0 - at(k + 2, k + 1) * y1;
    const double y3 = xd[k + 3] - at(k + 3, k) * y0 - at(k + 3, k + 1) * y1 - at(k + 3, k + 2) * y2;
    xd[k + 1] = y1;
    xd[k + 2] = y2;
    xd[k + 3] = y3;
    const double* c0 = a + k * n;
    const double* c1 = c0 + n;
    const double* c2 = c1 + n;
    const double* c3 = c2 + n;
    for (Index i = k + 4; i < n; ++i)
      xd[i] -= c0[i] * y0 + c1[i] * y1 + c2[i] * y2 + c3[i] * y3;
  }
  for (; k < n; ++k) {
    const double* col_k = a + k * n;
    const double yk = xd[k];
    for (Index i = k + 1; i < n; ++i)
      xd[i] -= col_k[i] * yk;
  }

  // U x = y, with 1/u_kk stored on the diagonal.
  Index e = n; // rows [e, n) are solved
  for (; e >= 4; e -= 4) {
    const Index k0 = e - 4;
    const double x3 = xd[k0 + 3] * at(k0 + 3, k0 + 3);
    const double x2 = (xd[k0 + 2] - at(k0 + 2, k0 + 3) * x3) * at(k0 + 2, k0 + 2);
    const double x1 =
        (xd[k0 + 1] - at(k0 + 1, k0 + 2) * x2 - at(k0 + 1, k0 + 3) * x3) * at(k0 + 1, k0 + 1);
    const double x0 =
        (xd[k0] - at(k0, k0 + 1) * x1 - at(k0, k0 + 2) * x2 - at(k0, k0 + 3) * x3) * at(k0, k0);
    xd[k0] = x0;
    xd[k0 + 1] = x1;
    xd[k0 + 2] = x2;
    xd[k0 + 3] = x3;
    const double* c0 = a + k0 * n;
    const double* c1 = c0 + n;
    const double* c2 = c1 + n;
    const double* c3 = c2 + n;
    for (Index i = 0; i < k0; ++i)
      xd[i] -= c0[i] * x0 + c1[i] * x1 + c2[i] * x2 + c3[i] * x3;
  }
  for (Index r = e - 1; r >= 0; --r) {
    const double* col_r = a + r * n;
    const double xr = xd[r] * col_r[r];
    xd[r] = xr;
    for (Index i = 0; i < r; ++i)
      xd[i] -= col_r[i] * xr;
  }
  content->last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

} // namespace

void accelerate_vector(N_Vector v) {
  if (v == nullptr || N_VGetVectorID(v) != SUNDIALS_NVEC_SERIAL) return;
  N_Vector_Ops ops = v->ops;
  ops->nvlinearsum = linear_sum;
  ops->nvconst = constant;
  ops->nvprod = prod;
  ops->nvdiv = divide;
  ops->nvscale = scale;
  ops->nvabs = absolute;
  ops->nvinv = inverse;
  ops->nvaddconst = add_const;
  ops->nvcompare = compare;
  ops->nvdotprod = dot;
  ops->nvmaxnorm = max_norm;
  ops->nvwrmsnorm = wrms_norm;
  ops->nvwrmsnormmask = wrms_norm_mask;
  ops->nvmin = min_value;
  ops->nvwl2norm = wl2_norm;
  ops->nvl1norm = l1_norm;
  ops->nvdotprodlocal = dot;
  ops->nvmaxnormlocal = max_norm;
  ops->nvminlocal = min_value;
  ops->nvl1normlocal = l1_norm;
  ops->nvwsqrsumlocal = wsqr_sum;
  ops->nvwsqrsummasklocal = wsqr_sum_mask;
  ops->nvlinearcombination = linear_combination;
  ops->nvscaleaddmulti = scale_add_multi;
  ops->nvdotprodmulti = dot_multi;
}

void accelerate_dense_solver(SUNLinearSolver s) {
  if (s == nullptr || SUNLinSolGetID(s) != SUNLINEARSOLVER_DENSE) return;
  s->ops->setup = dense_setup;
  s->ops->solve = dense_solve;
}

} // namespace thermnet::detail
