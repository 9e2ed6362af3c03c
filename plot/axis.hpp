#pragma once
/// An axis of a panel: its range, labelled ticks and grid lines, linear or logarithmic, and the
/// mapping of values to pixels.

#include "plot/ticks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace thermnet::plot {

/// One axis: its range and ticks in "transformed" space (log10 of the value on a log axis).
struct Axis {
  bool log = false;                ///< logarithmic
  double lo = 0, hi = 1;           ///< transformed range
  std::vector<double> major;       ///< transformed positions of labelled ticks
  std::vector<std::string> labels; ///< one per major tick
  std::vector<double> minor;       ///< transformed positions of unlabelled grid lines
  double p0 = 0, p1 = 1;           ///< pixel positions of lo and hi

  /// The transformed value of v (NaN for v <= 0 on a log axis).
  double transform(double v) const {
    if (!log) return v;
    return v > 0 ? std::log10(v) : std::numeric_limits<double>::quiet_NaN();
  }
  /// Pixel position of a transformed value.
  double pixel_t(double t) const { return p0 + (t - lo) / (hi - lo) * (p1 - p0); }
  /// Pixel position of a data value (NaN if it cannot be shown), clamped to a sane magnitude.
  double pixel(double v) const {
    const double t = transform(v);
    if (!std::isfinite(t)) return std::numeric_limits<double>::quiet_NaN();
    return std::clamp(pixel_t(t), -1e6, 1e6);
  }
};

/// How an axis range meets its ticks.
enum class Fit {
  extend, ///< the range grows to the outermost ticks
  snap,   ///< the range grows to a tick only when it is within 5 % of the span
  fixed   ///< the range is kept
};

/// A linear axis over lo..hi with at most max_ticks labelled ticks from `set`.
Axis linear_axis(double lo, double hi, Fit fit, int max_ticks, StepSet set);

/// A log axis over lo..hi (> 0, data space) labelling decades (and 2, 5 when decades are few).
Axis log_axis(double lo, double hi, Fit fit, int max_ticks);

/// The axis over the data range dlo..dhi, or over `fixed` (divided by fixed_divisor) when it is
/// given and drawable, kept as given.
Axis make_axis(bool log, double dlo, double dhi,
               const std::optional<std::pair<double, double>>& fixed, double fixed_divisor, Fit fit,
               int max_ticks, StepSet set);

/// Width in px of the widest tick label at font size `font`.
double max_label_width(const Axis& a, double font);

/// Smallest pixel distance between neighbouring labelled ticks (infinite with fewer than two).
double min_tick_gap(const Axis& a);

} // namespace thermnet::plot
