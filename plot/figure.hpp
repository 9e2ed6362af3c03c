#pragma once
/// What a chart shows: figures of panels holding series (curves) and bands.

#include <optional>
#include <string>
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
  /// Prefix of the SVG's element ids (letters, digits, '-' and '_'; others are dropped): figures
  /// inlined in one HTML page need distinct ones
  std::string id_prefix;
};

} // namespace thermnet::plot
