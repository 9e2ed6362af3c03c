#pragma once
/// Whiteness tests of a model's one-step-ahead prediction errors (innovations), as CTSM-R and
/// pySIP report them: the autocorrelation function with its ±1.96/√n bounds, and the cumulated
/// periodogram with its Kolmogorov-Smirnov bounds (R's cpgram). Innovations of a model that
/// describes the dynamics are white; structure left in them (a missing node, a daily input) shows
/// as autocorrelation beyond the bounds and a periodogram that leaves its band.

#include <cstddef>
#include <vector>

namespace thermnet {

/// The two tests of one series of innovations.
struct Whiteness {
  std::size_t n = 0;             ///< innovations tested
  double dt = 0.0;               ///< sampling interval, s (lag k is k dt)
  std::vector<double> acf;       ///< autocorrelation at lags 0..max lag (acf[0] = 1)
  double acf_bound = 0.0;        ///< 1.96/√n: the 95 % band of white noise
  std::size_t acf_outside = 0;   ///< lags 1..max lag outside the band
  std::size_t acf_allowed = 0;   ///< most lags outside the band white noise gives (99 %)
  std::size_t acf_peak_lag = 0;  ///< lag (>= 1) of the largest |acf|
  bool acf_white = true;         ///< acf_outside <= acf_allowed
  std::vector<double> frequency; ///< Fourier frequencies, 1/s (0 first)
  std::vector<double> cumulated; ///< cumulated periodogram at each frequency (0 .. 1)
  double ks_bound = 0.0;         ///< 95 % Kolmogorov-Smirnov half-width around the diagonal
  double ks_max = 0.0;           ///< largest distance of the cumulated periodogram from it
  bool cpgram_white = true;      ///< ks_max <= ks_bound
  /// Both tests pass.
  bool white() const { return acf_white && cpgram_white; }
};

/// Tests innovations sampled every dt seconds (missing values left out beforehand): the
/// autocorrelation up to `max_lag` (0: n/3, at most 200) and the cumulated periodogram of the
/// mean-removed series tapered by a split cosine bell over 10 % at each end (as R's cpgram).
/// Fewer than 8 values give an empty result that passes.
Whiteness test_whiteness(const std::vector<double>& innovations, double dt,
                         std::size_t max_lag = 0);

} // namespace thermnet
