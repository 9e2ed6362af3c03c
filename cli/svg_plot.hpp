#pragma once
/// A small self-contained SVG chart renderer for the plots of simulate/calibrate/diagnose (--plot).

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace thermnet::plot {

/// How a series is drawn.
enum class LineStyle {
  solid,       ///< continuous line (dash patterns cycle once the palette's colours run out)
  dashed,      ///< dashed line
  dotted,      ///< dotted line
  dash_dot,    ///< dash-dot line
  markers,     ///< small open markers only, no line (measured data)
  markers_line ///< line with markers on its points
};

/// One curve: y against x. Non-finite points (or, on log axes, non-positive ones) break the line.
struct Series {
  std::string label;     ///< legend text (empty: not listed in the legend)
  std::vector<double> x; ///< abscissae (seconds when Panel::x_is_time_s)
  std::vector<double> y; ///< ordinates (only the first min(x.size(), y.size()) are used)
  LineStyle style = LineStyle::solid; ///< line and marker style
  int color = -1;                     ///< palette index; -1: next colour of the panel's series
  double line_width = 1.5;            ///< stroke width in px
};

/// A filled band between lo and hi (e.g. min..max of an uncertainty study), drawn behind series.
struct Band {
  std::string label;      ///< legend text (empty: not listed in the legend)
  std::vector<double> x;  ///< abscissae
  std::vector<double> lo; ///< lower edge
  std::vector<double> hi; ///< upper edge
  int color = -1;         ///< palette index; -1: next band colour (band k matches series k)
};

/// One chart: axes, grid, series, bands and a legend to the right of the plot area.
struct Panel {
  std::string title;          ///< panel title (may be empty)
  std::string x_label;        ///< x axis label with its unit, e.g. "time [h]"
  std::string y_label;        ///< y axis label with its unit, e.g. "T [°C]"
  std::vector<Series> series; ///< curves, drawn in order
  std::vector<Band> bands;    ///< bands, drawn before the curves
  bool log_x = false;         ///< logarithmic x axis
  bool log_y = false;         ///< logarithmic y axis
  bool x_is_time_s = false;   ///< x is in seconds: shown in choose_time_axis()'s unit
  std::optional<std::pair<double, double>> x_range; ///< fixed x range, in the unit of Series::x
  std::optional<std::pair<double, double>> y_range; ///< fixed y range
};

/// A figure: a title over a grid of panels.
struct Figure {
  std::string title;         ///< figure title (may be empty)
  std::vector<Panel> panels; ///< panels, filled row by row
  int columns = 1;           ///< panels per row
  int width = 960;           ///< total width in px
  int panel_height = 420;    ///< height of each panel row in px
};

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

/// At most max_ticks (3 if 2 cannot do) "nice" ticks, 1-2-5 x 10^k apart, first <= lo, last >= hi.
Ticks nice_ticks(double lo, double hi, int max_ticks = 8);

/// Tick labels: decimals as the step needs, zeros trimmed, exponent form >= 1e6 or < 1e-3.
std::vector<std::string> tick_labels(const Ticks& ticks);

/// A number to `digits` significant digits, zeros trimmed ("0.3", "1.5e6", "-2e-5").
std::string format_number(double value, int digits = 6);

/// Text escaped for XML content and attributes; control characters become spaces, bad UTF-8 U+FFFD.
std::string xml_escape(std::string_view text);

/// Number of distinct colours in the palette (Okabe-Ito).
int palette_size();

/// Colour of a palette index as "#rrggbb" (indices wrap around).
std::string palette_color(int index);

/// Renders a figure as a standalone SVG 1.1 document (deterministic: same figure, same bytes).
std::string render_svg(const Figure& fig);

/// Renders a figure and writes it to a file; throws std::runtime_error if it cannot be written.
void write_svg(const Figure& fig, const std::string& path);

} // namespace thermnet::plot
