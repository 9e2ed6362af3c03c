#pragma once
/// How series look: the colour palette (Okabe-Ito), dash patterns and marker shapes that keep many
/// series distinguishable.

#include "plot/figure.hpp"

#include <string>

namespace thermnet::plot {

/// Radius of data markers in px.
inline constexpr double kMarkerRadius = 2.8;

/// Number of distinct colours in the palette (Okabe-Ito).
int palette_size();

/// Colour of a palette index as "#rrggbb" (indices wrap around).
std::string palette_color(int index);

/// The resolved look of a series (or a band's legend swatch).
struct Style {
  std::string color;    ///< "#rrggbb"
  std::string dash;     ///< stroke-dasharray ("" for solid)
  int shape = 0;        ///< marker shape (see append_marker)
  bool line = true;     ///< drawn as a line
  bool markers = false; ///< drawn with markers
};

/// The style of a series drawn with palette index `color_index`: solid lines cycle dash patterns
/// and markers cycle shapes each time the palette's colours run out.
Style series_style(const Series& s, int color_index);

/// Stroke width of a series, kept within 0.5..4 px.
double line_width_of(const Series& s);

} // namespace thermnet::plot
