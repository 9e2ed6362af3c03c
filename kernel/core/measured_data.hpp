#pragma once
/// Measured temperatures of one case, aligned with a network's nodes (kelvin inside).

#include "lang/csv.hpp"
#include "lang/network_spec.hpp"

#include <string>
#include <vector>

namespace thermnet {

/// One measured column: which node it names, and its samples (K, NaN where missing).
struct MeasuredSeries {
  std::string node;           ///< node or boundary name
  int node_index = -1;        ///< index in the NetworkSpec
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

/// Reads a case's data file and matches its columns to the spec's nodes; degC -> K. Rows after
/// the case's duration are left out. Throws lang::CsvError on a malformed file, a column that
/// names no node (row 1, that column) or no measured value within the duration.
MeasuredData load_measured(const std::string& path, const lang::NetworkSpec& spec);

} // namespace thermnet
