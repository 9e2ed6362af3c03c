// load_measured(): a case's CSV data file, read in the layout and with the column map its data
// statement gives, matched to the network's nodes; values in K.

#include "kernel/core/measured_data.hpp"

#include "lang/measured_series.hpp"

#include <fmt/format.h>

#include <cmath>

namespace thermnet {

std::size_t MeasuredData::points() const {
  std::size_t n = 0;
  for (const auto& s : series)
    for (double v : s.values)
      if (!std::isnan(v)) ++n;
  return n;
}

namespace {

/// The sensor (spec element) a series of `target` is compared with: the sensor so named, else the
/// one sensor that reads node `target` alone; -1 for none. Throws CsvError when several do.
int sensor_of(const lang::NetworkSpec& spec, const std::string& target, const std::string& path,
              std::size_t column) {
  const std::vector<int> sensors = lang::sensors_of_series(spec, target);
  if (sensors.empty()) return -1;
  if (sensors.size() == 1) return sensors.front();
  throw lang::CsvError(path, 1, column, lang::several_sensors_message(spec, target, sensors));
}

bool is_sensor(const lang::NetworkSpec& spec, const std::string& name) {
  for (const auto& el : spec.elements)
    if (el.schema && el.schema->observes && el.name == name) return true;
  return false;
}

} // namespace

double simulated_value(Network& net, const MeasuredSeries& s, double t, const double* x,
                       const double* all) {
  if (s.sensor < 0) return all[static_cast<std::size_t>(s.node_index)];
  return net.sensor_reading(static_cast<std::size_t>(s.sensor), t, x);
}

MeasuredData load_measured(const std::string& path, const lang::NetworkSpec& spec) {
  // The case's own data file is read as its data statement says (layout, unit, column map); any
  // other file (a command line's) in the default layout, every column naming a node.
  const bool own = path == spec.settings.data_path;
  lang::CaseSettings settings;
  if (own) settings = spec.settings;
  lang::CsvTable table = lang::read_csv(path, settings.data_layout);
  lang::check_measured(table);
  const std::vector<double> times = lang::case_times(table, settings);
  // Rows after the case's duration are not used (lint warns about them: data-beyond-duration).
  std::size_t used = times.size();
  if (spec.settings.duration) {
    const double end = *spec.settings.duration;
    const double last = end + 1e-9 * std::max(1.0, std::abs(end)); // the round-off of `end`
    while (used > 0 && times[used - 1] > last)
      --used;
  }
  MeasuredData data;
  data.path = path;
  data.times.assign(times.begin(), times.begin() + static_cast<long>(used));
  const auto series = lang::measured_series(table, settings, [&](const std::string& name) {
    return spec.node_index(name) >= 0 || is_sensor(spec, name);
  });
  for (const auto& v : series) {
    MeasuredSeries s;
    s.sensor = sensor_of(spec, v.target, path, v.column);
    const int index = s.sensor >= 0 ? spec.elements[static_cast<std::size_t>(s.sensor)].nodes()[0]
                                    : spec.node_index(v.target);
    if (index < 0)
      throw lang::CsvError(
          path, 1, v.column,
          fmt::format("'{}' names no node, boundary or sensor of the model", v.target));
    s.node = spec.nodes[static_cast<std::size_t>(index)].name;
    s.node_index = index;
    s.values.assign(v.kelvin.begin(), v.kelvin.begin() + static_cast<long>(used));
    data.series.push_back(std::move(s));
  }
  if (data.points() == 0)
    throw lang::CsvError(path, 1, 0,
                         fmt::format("no measured value within the case's duration of {:g} s",
                                     spec.settings.duration.value_or(0.0)));
  return data;
}

} // namespace thermnet
