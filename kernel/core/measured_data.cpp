// load_measured(): a case's CSV data file matched to the network's nodes, degC (or the unit the
// case declares for it) -> K.

#include "kernel/core/measured_data.hpp"

#include <fmt/format.h>

#include <cmath>

namespace thermnet {

namespace {
constexpr double kZeroCelsius = 273.15;
} // namespace

std::size_t MeasuredData::points() const {
  std::size_t n = 0;
  for (const auto& s : series)
    for (double v : s.values)
      if (!std::isnan(v)) ++n;
  return n;
}

MeasuredData load_measured(const std::string& path, const lang::NetworkSpec& spec) {
  lang::CsvTable table = lang::read_csv(path);
  lang::check_measured(table);
  // Rows after the case's duration are not used (lint warns about them: data-beyond-duration).
  const std::size_t used =
      table.rows() -
      (spec.settings.duration ? lang::rows_after(table, *spec.settings.duration) : 0);
  MeasuredData data;
  data.path = path;
  data.times.assign(table.time().begin(), table.time().begin() + static_cast<long>(used));
  // The case's own data file may declare its unit (`data "run.csv" [K]`): values to degC first.
  const bool own = path == spec.settings.data_path;
  const double scale = own ? spec.settings.data_scale : 1.0;
  const double offset = own ? spec.settings.data_offset : 0.0;
  for (std::size_t c = 1; c < table.columns.size(); ++c) {
    const std::string& name = table.columns[c];
    int index = spec.node_index(name);
    if (index < 0)
      throw lang::CsvError(path, 1, c + 1,
                           fmt::format("column '{}' names no node or boundary of the model", name));
    MeasuredSeries s;
    s.node = name;
    s.node_index = index;
    s.values.assign(table.cells[c].begin(), table.cells[c].begin() + static_cast<long>(used));
    for (double& v : s.values)
      if (!std::isnan(v)) v = scale * v + offset + kZeroCelsius;
    data.series.push_back(std::move(s));
  }
  if (data.points() == 0)
    throw lang::CsvError(path, 1, 0,
                         fmt::format("no measured value within the case's duration of {:g} s",
                                     spec.settings.duration.value_or(0.0)));
  return data;
}

} // namespace thermnet
