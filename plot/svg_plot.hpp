#pragma once
/// A small self-contained SVG chart renderer for the plots of simulate/calibrate/diagnose (--plot).

#include "plot/figure.hpp"

#include <string>

namespace thermnet::plot {

/// Renders a figure as a standalone SVG 1.1 document (deterministic: same figure, same bytes).
std::string render_svg(const Figure& fig);

} // namespace thermnet::plot
