#pragma once
/// The residual figure of the prediction criterion, as CTSM-R draws it: for each measured series,
/// the innovations' autocorrelation with its white-noise band and their cumulated periodogram with
/// its Kolmogorov-Smirnov band.

#include "kernel/calibration/innovation_report.hpp"
#include "plot/figure.hpp"

#include <string>
#include <vector>

namespace thermnet::app {

/// Two panels per series (autocorrelation against lag in hours; cumulated periodogram against
/// frequency in 1/h), side by side.
plot::Figure whiteness_figure(const std::vector<SeriesWhiteness>& tests, const std::string& title);

} // namespace thermnet::app
