#pragma once
/// Statistics of the diagnosis: how many independent points a residual holds, and whether two
/// fits (a missing link's linear and radiative mechanisms) are told apart by the data.

#include <cstddef>
#include <string>
#include <vector>

namespace thermnet {

/// Integrated autocorrelation time (>= 1 samples) of residual series from their pooled lag-1
/// autocorrelation rho, as for an AR(1) process: (1 + rho) / (1 - rho), capped at `cap`.
double autocorrelation_time(const std::vector<std::vector<double>>& series, double cap = 1e3);

/// Both fits of a comparison: residual series (same points, same order) and held-out SSE.
struct FitResiduals {
  std::vector<std::vector<double>> series; ///< residuals per measured series, K
  double holdout_sse = 0.0;                ///< SSE on data not used to fit, K^2
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

/// The paired held-out comparison of a candidate with a reference fit against measurement noise:
/// z = (SSE_ref - SSE_cand) / (2 noise ||r_ref - r_cand||) over the same held-out points. With
/// white noise of that level and the two predictions differing by r_ref - r_cand, the SSE
/// difference has that spread; positive: the candidate predicts the held-out data better; 0 when
/// there is nothing to compare.
double holdout_gain_z(const std::vector<double>& reference, const std::vector<double>& candidate,
                      double noise);

/// The z a held-out gain must reach to be more than chance (one-sided, about 1 in 10^4 per
/// comparison, margin for the many candidates compared).
inline constexpr double significant_gain_z = 3.5;

} // namespace thermnet
