#pragma once
/// Tick positions and labels: "nice" steps (1-2-5 x 10^k, or steps dividing hours and days on
/// time axes), the unit of time axes and the formatting of numbers.

#include <string>
#include <vector>

namespace thermnet::plot {

/// The unit in which time axes are shown.
struct TimeAxis {
  std::string unit;     ///< "s", "min" or "h"
  double divisor = 1.0; ///< seconds per unit (1, 60 or 3600)
};

/// Unit for a time axis reaching t_max_seconds: s up to 600 s, min up to 7200 s (2 h), h beyond.
TimeAxis choose_time_axis(double t_max_seconds);

/// Tick positions of a linear axis.
struct Ticks {
  std::vector<double> values; ///< tick positions, ascending, k * step exactly rounded
  double step = 1.0;          ///< distance between ticks: 1, 2 or 5 times a power of ten
};

/// Which tick steps an axis may use: 1-2-5 x 10^k, or for time axes also steps that divide
/// hours (15 min, 30 min) and days (3 h, 6 h, 12 h, 24 h, 1 week).
enum class StepSet {
  decimal, ///< 1-2-5 x 10^k
  minutes, ///< also 15 and 30 (min)
  hours    ///< also 3, 6, 12, 24, 48, ... 672 (h)
};

/// At most max_ticks (3 if 2 cannot do) ticks from `set`, first <= lo, last >= hi.
Ticks make_ticks(double lo, double hi, int max_ticks, StepSet set);

/// At most max_ticks (3 if 2 cannot do) "nice" ticks, 1-2-5 x 10^k apart, first <= lo, last >= hi.
Ticks nice_ticks(double lo, double hi, int max_ticks = 8);

/// Tick labels: decimals as the step needs, zeros trimmed, exponent form >= 1e6 or < 1e-3.
std::vector<std::string> tick_labels(const Ticks& ticks);

/// A number to `digits` significant digits, zeros trimmed ("0.3", "1.5e6", "-2e-5").
std::string format_number(double value, int digits = 6);

/// Widens a zero-width (or non-finite) range so it can be drawn.
void pad_if_flat(double& lo, double& hi);

} // namespace thermnet::plot
