#pragma once
/// Noise filters for uniformly sampled sensor signals, each giving smoothed values and their time
/// derivatives: Savitzky-Golay, Gaussian, moving average, or none (finite differences only).
///
/// Every filter works on a whole array in O(n) (the Savitzky-Golay moments come from chunked
/// prefix sums); a sliding Savitzky-Golay window reuses per-sample results instead
/// (savgol_kernel.hpp). Edges are treated without padding: Savitzky-Golay evaluates the first/last
/// full fit there (SciPy's mode 'interp'), the averaging filters shrink their window.

#include <cstddef>
#include <string>
#include <vector>

namespace thermnet::estimation {

/// Which filter to apply before fitting.
enum class FilterKind {
  none,           ///< raw samples, derivatives by second-order finite differences
  savgol,         ///< Savitzky-Golay: local least-squares polynomial, analytic derivative
  gaussian,       ///< Gaussian kernel (three matched box passes), then finite differences
  moving_average, ///< centred moving average, then finite differences
};

/// Parses "none", "savgol", "gaussian", "moving-average" (also "sg", "ma"); throws
/// std::invalid_argument listing the choices.
FilterKind parse_filter(const std::string& name);

/// The filter's name as parse_filter accepts it.
std::string filter_name(FilterKind kind);

/// A filter with its window (samples, odd) and Savitzky-Golay polynomial order.
struct FilterSpec {
  FilterKind kind = FilterKind::none; ///< which filter
  int window = 1;                     ///< samples covered (odd; clamped to the data length)
  int order = 3;                      ///< Savitzky-Golay polynomial order
};

/// Second-order finite differences: central inside, one-sided (three points) at both ends.
void finite_difference(const double* y, std::size_t n, double dt, double* slope);

/// Savitzky-Golay smoothing of order `order` over `window` samples (odd, > order, <= n): value and
/// first derivative of the local least-squares polynomial; edges use the first/last full fit.
void savitzky_golay(const double* y, std::size_t n, int window, int order, double dt, double* value,
                    double* slope);

/// Centred moving average over `window` samples (odd), shrinking symmetrically at the edges.
void moving_average(const double* y, std::size_t n, int window, double* out);

/// Gaussian smoothing with standard deviation window/6 samples, as three passes of a centred
/// moving average whose width matches that variance (the kernel spans about `window` samples).
void gaussian_smooth(const double* y, std::size_t n, int window, double* out);

/// Applies a filter: smoothed values and derivatives (per second) of n samples spaced dt apart.
void apply_filter(const FilterSpec& spec, const double* y, std::size_t n, double dt, double* value,
                  double* slope);

/// Trailing samples that fully determine the filtered value and derivative at the last sample, so
/// a stream can be filtered at its newest sample from its tail alone.
std::size_t filter_support(const FilterSpec& spec);

/// The filter's window for `n` samples: odd, at least order + 2 for Savitzky-Golay, at most n.
FilterSpec clamp_filter(FilterSpec spec, std::size_t n);

} // namespace thermnet::estimation
