#pragma once
/// One panel of a figure: axes, grid, labels, title, the data clipped to the plot area, legend.

#include "plot/figure.hpp"
#include "plot/svg_writer.hpp"

namespace thermnet::plot {

/// Draws panel `p` (the index-th of its figure, which names its clip path) into `cell`.
void render_panel(SvgWriter& o, const Panel& p, int index, Rect cell);

} // namespace thermnet::plot
