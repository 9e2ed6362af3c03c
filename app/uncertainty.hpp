#pragma once
/// The uncertainty bands' reports: CSV and SVG (the bands:
/// kernel/calibration/uncertainty_bands.hpp).

#include "kernel/calibration/uncertainty_bands.hpp"

#include <string>
#include <vector>

namespace thermnet::app {

/// Column label of a percentile: 5 -> "p5", 2.5 -> "p2.5".
std::string percentile_label(double q);

/// CSV text: `time`, then per node `NODE_min`, `NODE_pQ` for each percentile, `NODE_max` (degC).
std::string format_bands_csv(const UncertaintyBands& b);

/// SVG plot: per node (the named ones, all when empty) a min..max band, the median (or the
/// middle percentile) and the nominal run dashed; throws std::invalid_argument for unknown names.
std::string plot_bands_svg(const UncertaintyBands& b, const std::vector<std::string>& nodes,
                           const std::string& title);

} // namespace thermnet::app
