#pragma once
/// Statistics of the diagnosis: how many independent points a residual holds, and whether two
/// fits (a missing link's linear and radiative mechanisms) are told apart by the data.

#include <cstddef>
#include <string>
#include <vector>

namespace thermnet {

/// Residuals as the diagnosis keeps them between candidates (every refitted candidate's, on all
/// data and held out): single precision, half a double's memory; its rounding (6e-8 of a
/// residual) is far below any difference the tests between candidates resolve, and every sum
/// over them is taken in double precision.
using StoredResiduals = std::vector<float>;

/// The sum of the squares of r, in double precision.
double sum_of_squares(const StoredResiduals& r);

/// Integrated autocorrelation time (>= 1 samples) of residual series from their pooled lag-1
/// autocorrelation rho, as for an AR(1) process: (1 + rho) / (1 - rho), capped at `cap` (T:
/// float or double).
template <class T>
double autocorrelation_time(const std::vector<std::vector<T>>& series, double cap = 1e3);

/// Both fits of a comparison: residual series (same points, same order) and held-out SSE.
struct FitResiduals {
  std::vector<StoredResiduals> series; ///< residuals per measured series, K
  double holdout_sse = 0.0;            ///< SSE on data not used to fit, K^2
};

/// The outcome of comparing two non-nested fits with the same number of parameters.
struct FitComparison {
  double z = 0.0;              ///< SSE difference in units of the SSE's own sampling spread (>= 0)
  double tau = 1.0;            ///< autocorrelation time of the better fit's residuals, samples
  double n_eff = 0.0;          ///< independent points: n / tau
  bool first_better = true;    ///< the first fit has the lower SSE on all data
  bool holdout_agrees = false; ///< the better fit also has the lower held-out SSE
  bool separable = false;      ///< z >= threshold and held-out agrees
};

/// Compares two fits of the same data: the SSE difference is measured against the sampling spread
/// of an SSE at the residual level s^2 (the larger of noise^2 and the better fit's mean square)
/// over n_eff = n / tau independent points, sd = s^2 sqrt(2 n_eff), counted in independent points
/// (difference / tau). Separable when that z reaches `threshold` and the better fit also predicts
/// the held-out data better.
FitComparison compare_fits(const FitResiduals& a, const FitResiduals& b, double noise,
                           double threshold = 3.0);

/// The pooled autocorrelation of a series cut into consecutive segments of the given lengths
/// (none: one segment), each centred on its own mean, at lags 1, 2, ... up to the first lag where
/// it is no longer positive (Geyer's initial positive sequence) or `max_lag`: element k - 1 is
/// lag k. Empty for a series without correlation (T: float or double).
template <class T>
std::vector<double> positive_autocorrelation(const std::vector<T>& values,
                                             const std::vector<std::size_t>& segments = {},
                                             std::size_t max_lag = 1000);

/// The paired held-out comparison of a candidate with a reference fit, against the variation
/// neither explains: z = (SSE_ref - SSE_cand) / (2 s sqrt(d' R d)) over the same held-out points,
/// d = r_ref - r_cand, s^2 the larger of noise^2 and the candidate's mean square, and R the
/// correlation of the candidate's residuals within the segments (consecutive runs of samples of
/// one series; none: one run) as positive_autocorrelation() measures it. With white residuals at
/// the noise level (R = I, s = noise) the SSE difference has the spread 2 noise |d|; residuals
/// that keep a structure the candidate does not explain are correlated over many samples and
/// count as fewer independent points (for a slowly varying d, d' R d is |d|^2 times the
/// integrated autocorrelation time). Positive: the candidate predicts the held-out data better; 0
/// when there is nothing to compare (T: float or double).
template <class T>
double holdout_gain_z(const std::vector<T>& reference, const std::vector<T>& candidate,
                      double noise, const std::vector<std::size_t>& segments = {});

/// holdout_gain_z() with the candidate's positive_autocorrelation(candidate, segments) given
/// (measured once for a candidate tested against several references).
template <class T>
double holdout_gain_z(const std::vector<T>& reference, const std::vector<T>& candidate,
                      const std::vector<double>& candidate_rho, double noise,
                      const std::vector<std::size_t>& segments);

/// The largest drop of the RMS error over any `window` consecutive samples of one series:
/// max over windows of rms(reference) - rms(candidate) (series of the same lengths), K; what a
/// finding changes where it matters most (the practical floor of the significance rule).
template <class T>
double largest_window_gain(const std::vector<std::vector<T>>& reference,
                           const std::vector<std::vector<T>>& candidate, std::size_t window = 10);

/// The smallest relative drop of the held-out RMS error over the blocks (validation folds) of a
/// candidate against a reference: min over blocks of 1 - rms(candidate) / rms(reference), the
/// residuals of both laid out block after block (`blocks`: each block's number of points). A
/// value of 0.3 says that every block is predicted with at least 30 % less error. -inf without
/// blocks, or when the two do not cover the same points.
template <class T>
double worst_block_gain(const std::vector<T>& reference, const std::vector<T>& candidate,
                        const std::vector<std::size_t>& blocks);

/// The z a held-out gain must reach to be more than chance when many candidates are compared
/// (one-sided, about 2 in 10^4 per comparison).
inline constexpr double significant_gain_z = 3.5;

/// The z a held-out gain must reach when `compared` candidates are judged together: a one-sided
/// family-wise error of 1 % over them (Bonferroni, z = Phi^-1(1 - 0.01 / compared)), never above
/// significant_gain_z (the threshold validated on the scenario tables for hundreds).
double significant_gain_z_for(std::size_t compared);

} // namespace thermnet
