#pragma once
/// The legend to the right of a plot area: its layout (font size, columns, labels cut to fit, a
/// "+N more" line when entries do not fit) and its drawing.

#include "plot/style.hpp"
#include "plot/svg_writer.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace thermnet::plot {

/// Gap in px between the plot area and the legend.
inline constexpr double kLegendGap = 18;

/// One legend line: a swatch and a label.
struct LegendEntry {
  std::string label;  ///< sanitised text
  Style style;        ///< how the swatch looks
  double width = 1.5; ///< the line's stroke width
  bool band = false;  ///< a band's filled swatch instead of a line
};

/// Where and how large the legend's entries are drawn.
struct LegendLayout {
  double width = 0;        ///< including the gap before it
  double font = 12;        ///< font size in px
  double line_height = 16; ///< px per row
  double column_width = 0; ///< px per column, gap included
  int columns = 0;         ///< entry columns
  int rows = 0;            ///< rows per column
  std::size_t shown = 0;   ///< entries drawn (the rest summarised as "+N more")
  double label_width = 0;  ///< labels cut to this width in px
};

/// Chooses font size, columns and label width so the legend fits `height` and `max_width`:
/// first whole labels (shrinking the font, then wrapping into columns), then labels cut to no
/// less than 10 average characters, and at last a "+N more" line for what does not fit.
LegendLayout layout_legend(const std::vector<LegendEntry>& entries, double height,
                           double max_width);

/// Draws the legend with its top-left corner at (x0, y0).
void draw_legend(SvgWriter& o, const std::vector<LegendEntry>& entries, const LegendLayout& L,
                 double x0, double y0);

} // namespace thermnet::plot
