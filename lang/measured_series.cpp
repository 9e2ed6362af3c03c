#include "lang/measured_series.hpp"

#include "lang/display_text.hpp"
#include "lang/units.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

namespace thermnet::lang {
namespace {

/// Fails at the first value below absolute zero.
void check_above_absolute_zero(const CsvTable& t, const SeriesValues& s,
                               const std::vector<std::size_t>& columns) {
  for (std::size_t r = 0; r < s.kelvin.size(); ++r)
    if (s.kelvin[r] < 0.0) {
      std::size_t c = columns.front();
      for (std::size_t k : columns) // the column that brought the mean below 0 K: the lowest
        if (t.cells[k][r] < t.cells[c][r]) c = k;
      throw CsvError(t.path, t.line_of(r), t.file_columns[c],
                     fmt::format("{} is below absolute zero ({:.6g} degC) as a temperature of "
                                 "'{}' (is the file's unit the one it is read in?)",
                                 fmt::format("{:g}", t.cells[c][r]), s.kelvin[r] - kZeroCelsius,
                                 excerpt_for_display(s.target)));
    }
}

/// Fails at the first value above kMaxMeasuredKelvin: a cell like 1e300 is finite, but no
/// measurement is that hot, and its square overflows every sum of squares (RMSE inf, R² nan).
void check_below_ceiling(const CsvTable& t, const SeriesValues& s,
                         const std::vector<std::size_t>& columns) {
  for (std::size_t r = 0; r < s.kelvin.size(); ++r)
    if (s.kelvin[r] > kMaxMeasuredKelvin) {
      std::size_t c = columns.front();
      for (std::size_t k : columns) // the column that brought the mean above: the highest
        if (t.cells[k][r] > t.cells[c][r]) c = k;
      throw CsvError(
          t.path, t.line_of(r), t.file_columns[c],
          fmt::format("{:g} is too large for a temperature of '{}' ({:.6g} K; a measured "
                      "temperature is at most {:g} K: is the file's unit the one it is "
                      "read in?)",
                      t.cells[c][r], excerpt_for_display(s.target), s.kelvin[r],
                      kMaxMeasuredKelvin));
    }
}

} // namespace

void check_celsius_columns(const CsvTable& t) {
  for (std::size_t c = 1; c < t.columns.size(); ++c) {
    t.check_numbers(c);
    for (std::size_t r = 0; r < t.rows(); ++r)
      if (t.cells[c][r] < -kZeroCelsius)
        throw CsvError(t.path, t.line_of(r), t.file_columns[c],
                       fmt::format("{:g} degC is below absolute zero (-273.15 degC) in column '{}'",
                                   t.cells[c][r], excerpt_for_display(t.columns[c])));
      else if (t.cells[c][r] + kZeroCelsius > kMaxMeasuredKelvin)
        throw CsvError(t.path, t.line_of(r), t.file_columns[c],
                       fmt::format("{:g} degC is too large for a temperature (at most {:g} K) in "
                                   "column '{}'",
                                   t.cells[c][r], kMaxMeasuredKelvin,
                                   excerpt_for_display(t.columns[c])));
  }
}

std::vector<int> sensors_of_series(const NetworkSpec& spec, const std::string& target) {
  const int node = spec.node_index(target);
  std::vector<int> found;
  for (std::size_t e = 0; e < spec.elements.size(); ++e) {
    const auto& el = spec.elements[e];
    if (!el.schema || !el.schema->observes) continue;
    if (el.name == target) return {static_cast<int>(e)};
    if (node >= 0 && el.nodes().size() == 1 && el.nodes()[0] == node)
      found.push_back(static_cast<int>(e));
  }
  return found;
}

std::string several_sensors_message(const NetworkSpec& spec, const std::string& node,
                                    const std::vector<int>& sensors) {
  std::string names;
  for (int e : sensors)
    names += fmt::format("{}'{}'", names.empty() ? "" : ", ",
                         spec.elements[static_cast<std::size_t>(e)].name);
  return fmt::format("node '{}' is read by the sensors {}: name the sensor the series is compared "
                     "with (data \"FILE\" {{ SENSOR = COLUMN }})",
                     node, names);
}

std::vector<double> case_times(const CsvTable& t, const CaseSettings& s) {
  std::vector<double> times = t.time();
  if (t.absolute_time)
    for (double& x : times)
      x -= s.data_epoch;
  return times;
}

std::vector<SeriesValues> measured_series(const CsvTable& t, const CaseSettings& s,
                                          const std::function<bool(const std::string&)>& known) {
  std::vector<SeriesValues> out;
  const std::size_t rows = t.rows();
  if (!s.data_mapped) {
    for (std::size_t c = 1; c < t.columns.size(); ++c) {
      if (!known(t.columns[c]))
        throw CsvError(t.path, 1, t.file_columns[c],
                       fmt::format("column '{}' names no node or boundary of the model",
                                   excerpt_for_display(t.columns[c])));
      t.check_numbers(c);
      SeriesValues v{t.columns[c], std::vector<double>(rows), t.file_columns[c]};
      for (std::size_t r = 0; r < rows; ++r) {
        const double x = t.cells[c][r];
        v.kelvin[r] = std::isnan(x) ? x : s.data_scale * x + s.data_offset + kZeroCelsius;
      }
      check_above_absolute_zero(t, v, {c});
      check_below_ceiling(t, v, {c});
      out.push_back(std::move(v));
    }
    return out;
  }
  for (const DataSeries& d : s.data_series) {
    std::vector<std::size_t> columns;
    for (const std::string& name : d.columns) {
      const int c = t.column_index(name);
      if (c <= 0)
        throw CsvError(t.path, 1, 0,
                       c == 0 ? fmt::format("column '{}' is the time", excerpt_for_display(name))
                              : fmt::format("there is no column '{}'", excerpt_for_display(name)));
      t.check_numbers(static_cast<std::size_t>(c));
      columns.push_back(static_cast<std::size_t>(c));
    }
    SeriesValues v{d.target, std::vector<double>(rows), t.file_columns[columns.front()]};
    for (std::size_t r = 0; r < rows; ++r) {
      double mean = 0.0;
      for (std::size_t k = 0; k < columns.size(); ++k)
        mean += d.weights[k] * t.cells[columns[k]][r]; // a missing cell makes the mean missing
      v.kelvin[r] = std::isnan(mean) ? std::numeric_limits<double>::quiet_NaN()
                                     : d.scale * mean + d.offset + kZeroCelsius;
    }
    check_above_absolute_zero(t, v, columns);
    check_below_ceiling(t, v, columns);
    out.push_back(std::move(v));
  }
  return out;
}

} // namespace thermnet::lang
