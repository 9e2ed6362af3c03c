#pragma once
/// From data to pixels: series as polylines (broken at gaps, decimated per pixel column and
/// simplified), marker positions and band outlines.

#include "plot/axis.hpp"
#include "plot/figure.hpp"
#include "plot/svg_writer.hpp"

#include <cmath>
#include <vector>

namespace thermnet::plot {

/// Data to pixels in one plot area.
struct Mapping {
  const Axis* xa; ///< x axis (pixels set)
  const Axis* ya; ///< y axis (pixels set)
  double divisor; ///< x data units per displayed unit (time axes)
  Rect plot;      ///< the plot area

  /// The pixel position of (x, y) in p; false when it cannot be drawn.
  bool at(double x, double y, Point& p) const {
    if (!std::isfinite(x) || !std::isfinite(y)) return false;
    p.x = xa->pixel(x / divisor);
    p.y = ya->pixel(y);
    return std::isfinite(p.x) && std::isfinite(p.y);
  }
  /// The pixel column of x position px, clamped to just outside the plot area.
  long long column(double px) const {
    return static_cast<long long>(std::floor(std::clamp(px - plot.x, -1.0, plot.w + 1.0)));
  }
};

/// Series data as pixel polylines, decimated and then simplified to within 0.2 px.
std::vector<std::vector<Point>> line_segments(const Series& s, const Mapping& m);

/// Marker positions inside (or just outside) the plot; dense data keeps one marker per cell of
/// about a marker's size.
std::vector<Point> marker_points(const Series& s, const Mapping& m);

/// Band outlines: per run of finite points, the upper edge forward and the lower edge backward.
std::vector<std::vector<Point>> band_polygons(const Band& b, const Mapping& m);

} // namespace thermnet::plot
