#pragma once
/// Writing SVG text: coordinates rounded to 0.1 px, escaped text, and path data for polylines,
/// polygons and markers.

#include "plot/text.hpp"

#include <fmt/format.h>

#include <iterator>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace thermnet::plot {

/// A point in pixels.
struct Point {
  double x, y; ///< pixel coordinates, y downwards
};

/// A rectangle in pixels.
struct Rect {
  double x, y, w, h;                      ///< top-left corner, width and height
  double right() const { return x + w; }  ///< x of the right edge
  double bottom() const { return y + h; } ///< y of the bottom edge
};

/// The SVG document (or path data) being written.
struct SvgWriter {
  std::string s; ///< the text so far

  /// Appends formatted text.
  template <typename... A> void f(fmt::format_string<A...> fs, A&&... a) {
    fmt::format_to(std::back_inserter(s), fs, std::forward<A>(a)...);
  }
  /// Appends a coordinate rounded to 0.1 px, without a trailing ".0".
  void num(double v);
  /// Appends already sanitised text, escaped.
  void text(std::string_view sanitized) { append_escaped(s, sanitized); }
};

/// A coordinate as SvgWriter::num writes it.
std::string n1(double v);

/// Appends polylines as one path data string: "M x y L x y x y ..." per segment, repeated points
/// (to 0.1 px) dropped.
void append_polylines(SvgWriter& o, const std::vector<std::vector<Point>>& segs);

/// Appends closed polygons as one path data string.
void append_polygons(SvgWriter& o, const std::vector<std::vector<Point>>& polys);

/// Appends one marker of the given shape (0 circle, 1 square, 2 diamond, 3 triangle) at p.
void append_marker(SvgWriter& o, Point p, int shape, double r);

} // namespace thermnet::plot
