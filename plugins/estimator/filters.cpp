// Savitzky-Golay, Gaussian and moving-average filters (see filters.hpp).
//
// Savitzky-Golay in O(n): the fit centred at sample i needs the moments
// M_k(i) = sum_{|j|<=h} (j/h)^k y_{i+j}. They come from prefix sums of u^m y within chunks of h
// samples, u measured from the chunk's start in units of h, shifted to the centre by the binomial
// theorem. Shifts stay below 3 window half-widths, so no digits are lost whatever the length of
// the record (prefix sums over the whole record with one origin would cancel catastrophically).

#include "plugins/estimator/filters.hpp"
#include "plugins/estimator/savgol_kernel.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace thermnet::estimation {

FilterKind parse_filter(const std::string& name) {
  if (name == "none") return FilterKind::none;
  if (name == "savgol" || name == "sg" || name == "savitzky-golay") return FilterKind::savgol;
  if (name == "gaussian" || name == "gauss") return FilterKind::gaussian;
  if (name == "moving-average" || name == "ma" || name == "moving_average")
    return FilterKind::moving_average;
  throw std::invalid_argument("unknown filter '" + name +
                              "' (choose none, savgol, gaussian or moving-average)");
}

std::string filter_name(FilterKind kind) {
  switch (kind) {
  case FilterKind::none:
    return "none";
  case FilterKind::savgol:
    return "savgol";
  case FilterKind::gaussian:
    return "gaussian";
  case FilterKind::moving_average:
    return "moving-average";
  }
  return "none";
}

void finite_difference(const double* y, std::size_t n, double dt, double* slope) {
  if (n == 0) return;
  if (n == 1) {
    slope[0] = 0.0;
    return;
  }
  if (n == 2) {
    slope[0] = slope[1] = (y[1] - y[0]) / dt;
    return;
  }
  for (std::size_t i = 1; i + 1 < n; ++i)
    slope[i] = (y[i + 1] - y[i - 1]) / (2.0 * dt);
  slope[0] = (-3.0 * y[0] + 4.0 * y[1] - y[2]) / (2.0 * dt);
  slope[n - 1] = (3.0 * y[n - 1] - 4.0 * y[n - 2] + y[n - 3]) / (2.0 * dt);
}

namespace {

int half_width(int window) {
  return std::max(0, (window - 1) / 2);
}

// Chunked prefix moments of y: Q[m][g] = sum over the chunk of g, from its start to g - 1, of
// u^m y with u = (sample - chunk start) / h.
struct ChunkedMoments {
  std::size_t L;                      // chunk length (h)
  int p;                              // highest power
  double h;                           // unit of u
  std::vector<std::vector<double>> Q; // Q[m][g + chunk index] (one extra slot per chunk)

  ChunkedMoments(const double* y, std::size_t n, std::size_t chunk, int order)
      : L(chunk), p(order), h(static_cast<double>(chunk)) {
    std::size_t chunks = (n + L - 1) / L;
    Q.assign(static_cast<std::size_t>(p + 1), std::vector<double>(n + chunks, 0.0));
    for (std::size_t b = 0; b < chunks; ++b) {
      std::size_t start = b * L, end = std::min(n, start + L);
      std::vector<double> acc(static_cast<std::size_t>(p + 1), 0.0);
      for (std::size_t g = start; g < end; ++g) {
        double u = static_cast<double>(g - start) / h, pw = y[g];
        for (int m = 0; m <= p; ++m) {
          acc[m] += pw;
          Q[m][g + b + 1] = acc[m];
          pw *= u;
        }
      }
    }
  }

  // Adds sum_{g=lo..hi} ((g - centre)/h)^k y_g for k = 0..p to M (lo..hi inside one chunk).
  void add_range(std::size_t lo, std::size_t hi, std::size_t centre, double* M,
                 const std::vector<std::vector<double>>& binom) const {
    std::size_t b = lo / L;
    std::size_t start = b * L;
    double d = (static_cast<double>(centre) - static_cast<double>(start)) / h;
    double S[16];
    for (int m = 0; m <= p; ++m)
      S[m] = Q[m][hi + b + 1] - Q[m][lo + b];
    for (int k = 0; k <= p; ++k) {
      double acc = 0.0, pw = 1.0; // (-d)^(k - m), m from k down to 0
      for (int m = k; m >= 0; --m) {
        acc += binom[k][m] * pw * S[m];
        pw *= -d;
      }
      M[k] += acc;
    }
  }
};

} // namespace

void savitzky_golay(const double* y, std::size_t n, int window, int order, double dt, double* value,
                    double* slope) {
  if (window % 2 == 0 || window < 1 || static_cast<std::size_t>(window) > n || order < 0 ||
      order >= window || order > 12)
    throw std::invalid_argument("Savitzky-Golay needs an odd window <= the data length and an "
                                "order below the window (at most 12)");
  const int h = half_width(window);
  const int p = order;
  if (h == 0) {
    std::copy(y, y + n, value);
    finite_difference(y, n, dt, slope);
    return;
  }
  const Eigen::MatrixXd Ginv = savgol_gram_inverse(h, p);
  std::vector<std::vector<double>> binom(p + 1, std::vector<double>(p + 1, 0.0));
  for (int k = 0; k <= p; ++k) {
    binom[k][0] = 1.0;
    for (int m = 1; m <= k; ++m)
      binom[k][m] = binom[k - 1][m - 1] + (m <= k - 1 ? binom[k - 1][m] : 0.0);
  }
  ChunkedMoments moments(y, n, static_cast<std::size_t>(h), p);
  const std::size_t uh = static_cast<std::size_t>(h);
  Eigen::VectorXd M(p + 1), a(p + 1);
  auto fit_at = [&](std::size_t centre) {
    M.setZero();
    std::size_t lo = centre - uh, hi = centre + uh;
    while (lo <= hi) {
      std::size_t chunk_end = (lo / uh + 1) * uh - 1;
      std::size_t top = std::min(hi, chunk_end);
      moments.add_range(lo, top, centre, M.data(), binom);
      lo = top + 1;
    }
    a.noalias() = Ginv * M;
  };
  auto eval = [&](std::size_t g, std::size_t centre) {
    double s = (static_cast<double>(g) - static_cast<double>(centre)) / h;
    double v = 0.0, dv = 0.0, pw = 1.0;
    for (int k = 0; k <= p; ++k) {
      v += a[k] * pw;
      if (k + 1 <= p) dv += (k + 1) * a[k + 1] * pw;
      pw *= s;
    }
    value[g] = v;
    slope[g] = dv / (h * dt);
  };
  const std::size_t first = uh, last = n - 1 - uh;
  fit_at(first);
  for (std::size_t g = 0; g < first; ++g)
    eval(g, first);
  // Inside, only the value and slope rows of G^-1 are needed (the hot loop of a sliding window).
  double r0[16], r1[16];
  for (int k = 0; k <= p; ++k) {
    r0[k] = Ginv(0, k);
    r1[k] = p > 0 ? Ginv(1, k) : 0.0;
  }
  for (std::size_t i = first; i <= last; ++i) {
    double m[16] = {0.0};
    std::size_t lo = i - uh, hi = i + uh;
    while (lo <= hi) {
      std::size_t top = std::min(hi, (lo / uh + 1) * uh - 1);
      moments.add_range(lo, top, i, m, binom);
      lo = top + 1;
    }
    double v = 0.0, dv = 0.0;
    for (int k = 0; k <= p; ++k) {
      v += r0[k] * m[k];
      dv += r1[k] * m[k];
    }
    value[i] = v;
    slope[i] = dv / (h * dt);
  }
  fit_at(last);
  for (std::size_t g = last + 1; g < n; ++g)
    eval(g, last);
}

void moving_average(const double* y, std::size_t n, int window, double* out) {
  std::vector<double> prefix(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    prefix[i + 1] = prefix[i] + y[i];
  const std::size_t h = static_cast<std::size_t>(half_width(window));
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t r = std::min({h, i, n - 1 - i});
    out[i] = (prefix[i + r + 1] - prefix[i - r]) / static_cast<double>(2 * r + 1);
  }
}

namespace {
int gaussian_box_width(int window) {
  double sigma = window / 6.0;
  int w = static_cast<int>(std::lround(std::sqrt(4.0 * sigma * sigma + 1.0)));
  if (w % 2 == 0) ++w;
  return std::max(1, w);
}
} // namespace

void gaussian_smooth(const double* y, std::size_t n, int window, double* out) {
  const int w = gaussian_box_width(window);
  std::vector<double> a(y, y + n), b(n);
  moving_average(a.data(), n, w, b.data());
  moving_average(b.data(), n, w, a.data());
  moving_average(a.data(), n, w, out);
}

void apply_filter(const FilterSpec& spec, const double* y, std::size_t n, double dt, double* value,
                  double* slope) {
  switch (spec.kind) {
  case FilterKind::none:
    std::copy(y, y + n, value);
    break;
  case FilterKind::savgol:
    savitzky_golay(y, n, spec.window, spec.order, dt, value, slope);
    return;
  case FilterKind::gaussian:
    gaussian_smooth(y, n, spec.window, value);
    break;
  case FilterKind::moving_average:
    moving_average(y, n, spec.window, value);
    break;
  }
  finite_difference(value, n, dt, slope);
}

std::size_t filter_support(const FilterSpec& spec) {
  switch (spec.kind) {
  case FilterKind::none:
    return 3;
  case FilterKind::savgol:
    return static_cast<std::size_t>(spec.window) + 2;
  case FilterKind::gaussian:
    return 3 * static_cast<std::size_t>(half_width(gaussian_box_width(spec.window))) + 3;
  case FilterKind::moving_average:
    return static_cast<std::size_t>(half_width(spec.window)) + 3;
  }
  return 3;
}

FilterSpec clamp_filter(FilterSpec spec, std::size_t n) {
  int limit = static_cast<int>(std::min<std::size_t>(n, 1u << 30));
  if (limit % 2 == 0) --limit;
  spec.window = std::max(1, std::min(spec.window, limit));
  if (spec.window % 2 == 0) ++spec.window;
  if (spec.window > limit) spec.window -= 2;
  if (spec.kind == FilterKind::savgol) {
    spec.order = std::max(0, spec.order);
    if (spec.window <= spec.order)
      spec.window = std::min(limit, spec.order + (spec.order % 2 == 0 ? 1 : 2));
    if (spec.window <= spec.order) spec.order = std::max(0, spec.window - 1);
  }
  return spec;
}

} // namespace thermnet::estimation
