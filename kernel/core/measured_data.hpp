#pragma once
/// Measured temperatures of one case, aligned with a network's nodes (kelvin inside).

#include "kernel/core/network.hpp"
#include "lang/csv.hpp"
#include "lang/network_spec.hpp"

#include <string>
#include <vector>

namespace thermnet {

/// One measured series: which node it measures (through which sensor), and its samples (K, NaN
/// where missing).
struct MeasuredSeries {
  std::string node;           ///< node or boundary name (a sensor's: the node it reads)
  int node_index = -1;        ///< index in the NetworkSpec (a sensor's: its first node)
  int sensor = -1;            ///< spec element of the sensor whose reading it is, or -1
  std::vector<double> values; ///< one per time, K; NaN = missing
};

/// A case's measured data: sample times and one series per measured node.
struct MeasuredData {
  std::string path;                   ///< file it came from
  std::vector<double> times;          ///< sample times, s, increasing
  std::vector<MeasuredSeries> series; ///< measured nodes
  /// Number of non-missing samples.
  std::size_t points() const;
};

/// Reads a case's data file (in the layout and with the column map of its data statement) and
/// matches its series to the spec's nodes and sensors: a series naming a sensor, or a node that
/// exactly one sensor reads, is compared with that sensor's reading; degC -> K. Rows after the
/// case's duration are left out. Throws lang::CsvError on a malformed file, a series that names
/// no node or sensor (row 1, that column) or no measured value within the duration.
MeasuredData load_measured(const std::string& path, const lang::NetworkSpec& spec);

/// The simulated counterpart of a measured series at (t, x) (x: the network's unknowns, `all`:
/// Network::expand of them): its node's temperature, or its sensor's reading, K.
double simulated_value(Network& net, const MeasuredSeries& s, double t, const double* x,
                       const double* all);

} // namespace thermnet
