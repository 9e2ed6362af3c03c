#pragma once
/// One panel of a figure: axes, grid, labels, title, the data clipped to the plot area, legend.

#include "plot/figure.hpp"
#include "plot/svg_writer.hpp"

#include <string>

namespace thermnet::plot {

/// Draws panel `p` into `cell`; `clip_id` is the id of its clip path (unique in the document).
void render_panel(SvgWriter& o, const Panel& p, const std::string& clip_id, Rect cell);

} // namespace thermnet::plot
