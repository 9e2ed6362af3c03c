#pragma once
/// The measured series of a case's data file, as its data statement maps them: each compared with
/// a node, boundary or sensor, read from one column or the weighted mean of several, in the unit
/// written, with the case's time from its start.

#include "lang/csv.hpp"
#include "lang/network_spec.hpp"

#include <functional>
#include <string>
#include <vector>

namespace thermnet::lang {

/// One measured series: what it is compared with, and its values in K (NaN where missing).
struct SeriesValues {
  std::string target;         ///< node, boundary or sensor
  std::vector<double> kelvin; ///< one per row of the file
  std::size_t column = 0;     ///< the file's (first) column it is read from, 1-based
};

/// The largest measured temperature accepted, K: hotter than any material a thermal network
/// models (a cell above it is an error, like `inf`: its square would overflow the fit's sums).
inline constexpr double kMaxMeasuredKelvin = 1e6;

/// The times of a data file's rows from the case's start, s (absolute layouts: minus the epoch).
std::vector<double> case_times(const CsvTable& t, const CaseSettings& s);

/// The series of a case's data file `t` (read with s.data_layout): without a column map every
/// column other than the time names its target; with one, only the map's. Throws CsvError (row
/// and column) on a column that names nothing `known` accepts, a column the map names that the
/// file lacks, on/off words in a temperature column and a temperature below absolute zero or
/// above kMaxMeasuredKelvin.
std::vector<SeriesValues> measured_series(const CsvTable& t, const CaseSettings& s,
                                          const std::function<bool(const std::string&)>& known);

/// The sensors (indices in spec.elements) a series of `target` may be compared with: the sensor
/// so named, else every sensor that reads node `target` alone. One: the series is that sensor's
/// reading; several: the series must name the sensor (an error); none: the node itself.
std::vector<int> sensors_of_series(const NetworkSpec& spec, const std::string& target);

/// Why a series of node `node` read by several `sensors` (sensors_of_series()) cannot be compared:
/// their names, and how to name the one it comes from.
std::string several_sensors_message(const NetworkSpec& spec, const std::string& node,
                                    const std::vector<int>& sensors);

/// Checks a table whose every column after the time holds temperatures in degC (the data of
/// `thermnet estimate` and `invert`): numbers or missing cells only, none below absolute zero or
/// above kMaxMeasuredKelvin;
/// throws CsvError at the first bad cell's row and column.
void check_celsius_columns(const CsvTable& t);

} // namespace thermnet::lang
