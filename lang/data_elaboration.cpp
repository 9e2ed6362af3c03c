// The data statement of a case: the measured file, its layout (time column, unit or format,
// separator), its column map (a node, boundary or sensor = a column or a weighted mean of
// columns), and lint's checks of the file against the model.

#include "lang/display_text.hpp"
#include "lang/elaborator.hpp"
#include "lang/elaborator_detail.hpp"
#include "lang/measured_series.hpp"
#include "lang/units.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace thermnet::lang {
using namespace detail;

namespace {

namespace fs = std::filesystem;

/// The temperatures a model prescribes, in degC: boundaries (over their signals), initial
/// temperatures of nodes and of the case.
std::pair<double, double> prescribed_band(const NetworkSpec& net) {
  double lo = net.default_initial(), hi = lo;
  auto take = [&](double k) {
    lo = std::min(lo, k);
    hi = std::max(hi, k);
  };
  const double end = net.settings.duration.value_or(0.0);
  for (const auto& n : net.nodes) {
    if (n.T0) take(*n.T0);
    if (!n.boundary) continue;
    if (n.T.kind() == Signal::Kind::expression) {
      for (int k = 0; k <= 10; ++k)
        take(n.T.at(end * k / 10.0));
    } else {
      take(n.T.constant);
      for (double v : n.T.values())
        take(v);
      if (!n.T.is_constant()) take(n.T.values().empty() ? n.T.constant : n.T.values().front());
    }
  }
  return {lo - kZeroCelsius, hi - kZeroCelsius};
}

/// True when `name` is a node, a boundary or a sensor of the model: what a series is compared with.
bool measurable(const Model& m, const std::string& name) {
  if (m.node_index(name) >= 0) return true;
  const int e = m.element_index(name);
  if (e < 0) return false;
  const ElementDecl& d = m.elements()[static_cast<std::size_t>(e)];
  return d.schema && d.schema->observes;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

} // namespace

void Elaborator::apply_data(NetworkSpec& net, const ast::CaseData& data, const Scope* scope,
                            std::set<std::string>& seen) {
  const FileId f = case_->file;
  CaseSettings& s = net.settings;
  const Span at{f, data.begin, data.begin};
  if (scope) {
    report(DiagnosticEngine::make(DiagId::misplaced_statement, at, span_of(f, data),
                                  "'data' is given once per case, not in a loop"));
    return;
  }
  if (!seen.insert("data").second) {
    report(
        DiagnosticEngine::make(DiagId::duplicate_case_key, at, span_of(f, data), s.name, "data"));
    return;
  }
  fs::path p(data.path.text);
  if (p.is_relative()) p = fs::path(m_.directory_of(f)) / p;
  s.data_path = p.lexically_normal().string();
  s.data_where = span_of(f, data);
  std::optional<Unit> unit;
  if (data.unit) {
    unit = temperature_unit(*data.unit, f, at, "the unit of a data file");
    if (unit) {
      s.data_scale = unit->scale;
      s.data_offset = unit->offset - kZeroCelsius; // to degC, the unit of data files
    }
  }
  // The layout is read (and its problems reported) once, where tables of the file need it too.
  const CaseDataFile* file = &data == first_data_statement() ? case_data_file() : nullptr;
  if (!file) return;
  s.data_layout = file->layout;
  s.data_epoch = file->epoch;
  if (data.mapped && !column_map(net, data)) return;
  if (check_data_) check_data(net, at, span_of(f, data.path), unit);
}

const ast::CaseData* Elaborator::first_data_statement() const {
  if (!case_) return nullptr;
  for (const auto& item : case_->stmt->items)
    if (const auto* d = std::get_if<ast::CaseData>(&item)) return d;
  return nullptr;
}

std::optional<Unit> Elaborator::temperature_unit(const ast::UnitText& text, FileId f, Span at,
                                                 const char* what) {
  try {
    Unit u = parse_unit(text.text);
    if (u.dim == dim::temperature) return u;
    report(DiagnosticEngine::make(DiagId::unit_mismatch, at, span_of(f, text), what,
                                  describe(dim::temperature), describe(u.dim)));
  } catch (const UnitError& e) {
    report(DiagnosticEngine::make(DiagId::unknown_unit, at, span_of(f, text), e.what()));
  }
  return std::nullopt;
}

// `{ air = mean(t2, t3); room = t1 [K] }`: each entry names a node or boundary and the columns
// whose weighted mean it is compared with (weights normalised, positive).
bool Elaborator::column_map(NetworkSpec& net, const ast::CaseData& data) {
  const FileId f = case_->file;
  CaseSettings& s = net.settings;
  s.data_mapped = true;
  bool ok = true;
  for (const ast::ColumnMap& cm : data.columns) {
    const Span at{f, cm.begin, cm.begin};
    DataSeries d;
    d.where = span_of(f, cm);
    try {
      d.target = reference_text(cm.target, f, nullptr);
    } catch (const EvalError& e) {
      report_at(e, at);
      ok = false;
      continue;
    }
    if (!measurable(m_, d.target)) {
      if (!m_.declared_by_unparsed(d.target)) {
        Diagnostic diag =
            DiagnosticEngine::make(DiagId::unknown_node, at, span_of(f, cm.target), d.target);
        std::vector<std::string> names;
        for (const auto& n : m_.nodes())
          names.emplace_back(n.name);
        if (auto sug = closest_match(d.target, names))
          diag.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *sug));
        report(std::move(diag));
      }
      ok = false;
      continue;
    }
    if (std::any_of(s.data_series.begin(), s.data_series.end(),
                    [&](const DataSeries& o) { return o.target == d.target; })) {
      report(DiagnosticEngine::make(
          DiagId::duplicate_case_key, at, span_of(f, cm.target), s.name,
          fmt::format("the measured series of '{}' (in its data statement)", d.target)));
      ok = false;
      continue;
    }
    double total = 0.0;
    for (const ast::ColumnSource& src : cm.sources) {
      double w = 1.0;
      if (src.weight) {
        if (!cm.mean) {
          report(DiagnosticEngine::make(DiagId::bad_signal, at, span_of(f, *src.weight),
                                        "a weight stands in a mean: mean(a: 2, b: 1)"));
          ok = false;
          continue;
        }
        static const KeySchema weight = [] {
          KeySchema k;
          k.min = 0.0;
          k.min_exclusive = true;
          return k;
        }();
        Place place{[] { return std::string("the weight of a column in a mean"); }, Dimension{},
                    false, &weight};
        auto x = number(*src.weight, f, place, at);
        if (!x) {
          ok = false;
          continue;
        }
        w = *x;
      }
      d.columns.push_back(src.column.text);
      d.weights.push_back(w);
      total += w;
    }
    if (d.columns.empty()) continue; // every column refused (reported above): no series
    // Normalised by the largest weight first: the sum of weights near 1e308 would overflow.
    const double largest = *std::max_element(d.weights.begin(), d.weights.end());
    total = 0.0;
    for (double& w : d.weights)
      total += w /= largest;
    for (double& w : d.weights)
      w /= total;
    d.scale = s.data_scale;
    d.offset = s.data_offset;
    if (cm.unit) {
      auto u = temperature_unit(*cm.unit, f, at, "the unit of a measured column");
      if (!u) {
        ok = false;
        continue;
      }
      d.scale = u->scale;
      d.offset = u->offset - kZeroCelsius;
    }
    s.data_series.push_back(std::move(d));
  }
  if (ok && s.data_series.empty()) {
    report(DiagnosticEngine::make(DiagId::bad_signal, s.data_where, s.data_where,
                                  "the data statement's column map names no series"));
    ok = false;
  }
  return ok;
}

// Lint reads the file: its rows and cells, its columns against the model (or the column map),
// and whether its values are probably in another unit than the one they are read in.
void Elaborator::check_data(const NetworkSpec& net, Span at, Span mark,
                            const std::optional<Unit>& unit) {
  const CaseSettings& s = net.settings;
  const std::string& path = s.data_path;
  try {
    auto table = m_.tables().get(path, s.data_layout);
    const CsvTable& t = *table;
    CsvTable times;
    times.path = path;
    times.columns = {t.columns[0]};
    times.cells = {case_times(t, s)};
    times.file_columns = {t.file_columns[0]};
    times.lines = t.lines;
    check_measured(t);
    data_times_ = DataTimes{std::move(times), at, mark};
    bool known_columns = true;
    if (!s.data_mapped) {
      for (std::size_t c = 1; c < t.columns.size(); ++c) {
        if (measurable(m_, t.columns[c]) || m_.declared_by_unparsed(t.columns[c])) continue;
        known_columns = false;
        Diagnostic d = DiagnosticEngine::make(DiagId::data_unknown_column, at, mark, t.columns[c]);
        d.message += fmt::format(" (in {}, column {})", fs::path(path).filename().string(),
                                 t.file_columns[c]);
        std::vector<std::string> names;
        for (const auto& n : net.nodes)
          names.push_back(n.name);
        if (auto sug = closest_match(t.columns[c], names))
          d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *sug));
        else
          d.notes.push_back(DiagnosticEngine::note(
              DiagId::note_text, std::nullopt,
              "to compare only some columns, map them: data \"FILE\" { NODE = COLUMN }"));
        report(std::move(d));
      }
    } else {
      for (const DataSeries& series : s.data_series)
        for (const std::string& c : series.columns) {
          if (t.column_index(c) > 0) continue;
          known_columns = false;
          Diagnostic d = DiagnosticEngine::make(
              DiagId::data_missing_column,
              Span{series.where.file, series.where.begin, series.where.begin}, series.where,
              fs::path(path).filename().string(), excerpt_for_display(c));
          if (auto sug = closest_match(c, t.columns))
            d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *sug));
          report(std::move(d));
        }
    }
    if (!known_columns) return;
    const auto series = measured_series(t, s, [](const std::string&) { return true; });
    // A series of a node that several sensors read is compared with none of them (which one?).
    for (const auto& v : series) {
      const std::vector<int> sensors = sensors_of_series(net, v.target);
      if (sensors.size() < 2) continue;
      const auto entry = std::find_if(s.data_series.begin(), s.data_series.end(),
                                      [&](const DataSeries& d) { return d.target == v.target; });
      if (entry != s.data_series.end()) {
        report(
            DiagnosticEngine::make(DiagId::data_sensor_ambiguous,
                                   Span{entry->where.file, entry->where.begin, entry->where.begin},
                                   entry->where, several_sensors_message(net, v.target, sensors)));
      } else {
        report(DiagnosticEngine::make(DiagId::data_sensor_ambiguous, at, mark,
                                      fmt::format("{} (column {} of {})",
                                                  several_sensors_message(net, v.target, sensors),
                                                  v.column, fs::path(path).filename().string())));
      }
    }
    bool any = false;
    for (const auto& v : series)
      any = any ||
            std::any_of(v.kelvin.begin(), v.kelvin.end(), [](double x) { return !std::isnan(x); });
    if (!any)
      throw CsvError(path, 1, 0, "no measured value: the series it is read for hold no number");
    // Values hundreds of kelvin away from every temperature the model prescribes are most likely
    // in another unit than the one they are read in (a fit would invent a huge heater).
    constexpr double far = 150.0;
    const auto [lo, hi] = prescribed_band(net);
    std::vector<double> medians;
    std::string columns;
    for (const auto& v : series) {
      std::vector<double> x;
      for (double k : v.kelvin)
        if (!std::isnan(k)) x.push_back(k - kZeroCelsius);
      if (x.empty()) continue;
      const double m = median(std::move(x));
      if (m > lo - far && m < hi + far) return; // a column in the model's range: the unit fits
      medians.push_back(m);
      if (medians.size() <= 3)
        columns += fmt::format("{}'{}'", columns.empty() ? "" : ", ", v.target);
    }
    if (medians.empty()) return;
    const double m = median(medians);
    const char* read_as = unit ? "in the declared unit" : "as degC";
    std::string guess;
    if (m - kZeroCelsius > lo - far / 3 && m - kZeroCelsius < hi + far / 3)
      guess = " They look like kelvin: write data \"FILE\" [K].";
    else if ((m - 32) / 1.8 > lo - far / 3 && (m - 32) / 1.8 < hi + far / 3)
      guess = " They look like degF: write data \"FILE\" [degF].";
    else if (unit && m + kZeroCelsius > lo - far / 3 && m + kZeroCelsius < hi + far / 3)
      guess = " They look like degC: drop the unit.";
    report(DiagnosticEngine::make(
        DiagId::data_unit_suspect, at, mark,
        fmt::format("the measured values of {} (median {:.4g} degC read {}) lie more than {:g} K "
                    "from every temperature the model prescribes ({:.4g} .. {:.4g} degC): are "
                    "they in another unit?{}",
                    columns, m, read_as, far, lo, hi, guess)));
  } catch (const CsvError& e) {
    if (e.row == 0)
      report(DiagnosticEngine::make(DiagId::data_unreadable, at, mark, path, e.detail));
    else
      report(DiagnosticEngine::make(DiagId::data_format, at, mark, e.what()));
  }
}

// `initial = data`: a node measured directly starts at the first measured value of its series,
// unless it has a T0. A series compared with a sensor's reading (it names the sensor, or the one
// node a single sensor reads) starts the sensor's nodes so that the reading equals that value:
// through the sensor's offset and gain, and for a sensor of several nodes the nodes without a
// start (nor a series of their own) share what the others leave. The kernel starts the other
// nodes at the steady state around those (start_state()).
void Elaborator::initial_from_data(NetworkSpec& net) {
  const CaseSettings& s = net.settings;
  const Span at{case_->file, s.where.begin, s.where.begin};
  if (s.data_path.empty()) {
    if (case_->stmt->unparsed_data) return; // its syntax error is reported
    report(DiagnosticEngine::make(DiagId::bad_signal, at, case_->name_span,
                                  fmt::format("'initial = data' of case '{}' needs a data "
                                              "statement",
                                              s.name)));
    return;
  }
  try {
    auto table = m_.tables().get(s.data_path, s.data_layout);
    const auto series =
        measured_series(*table, s, [&](const std::string& name) { return measurable(m_, name); });
    struct Start {
      std::vector<int> sensors; // what the series is compared with (several: ambiguous)
      double kelvin = 0.0;      // its first measured value
      int node = -1;            // the node it is, when no sensor reads it
    };
    std::vector<Start> starts;
    for (const auto& v : series) {
      auto first =
          std::find_if(v.kelvin.begin(), v.kelvin.end(), [](double x) { return !std::isnan(x); });
      if (first == v.kelvin.end()) continue;
      starts.push_back({sensors_of_series(net, v.target), *first, net.node_index(v.target)});
    }
    // Nodes measured directly first: a sensor of several nodes counts them as known.
    for (const Start& st : starts) {
      if (!st.sensors.empty() || st.node < 0) continue;
      NodeSpec& n = net.nodes[static_cast<std::size_t>(st.node)];
      if (!n.boundary && !n.T0) n.T0 = st.kelvin;
    }
    for (const Start& st : starts) {
      if (st.sensors.size() != 1) continue; // several: lint reports it (check_data)
      const ElementSpec& e = net.elements[static_cast<std::size_t>(st.sensors.front())];
      // The reading is offset + gain * mean(T) in degC: the mean that reads the measured value.
      const double mean = (st.kelvin - kZeroCelsius - e.values.at("offset").constant) /
                              e.values.at("gain").constant +
                          kZeroCelsius;
      double known = 0.0;
      std::vector<NodeSpec*> free;
      for (int node : e.nodes()) {
        NodeSpec& n = net.nodes[static_cast<std::size_t>(node)];
        if (n.boundary)
          known += n.T.at(0.0);
        else if (n.T0)
          known += *n.T0;
        else
          free.push_back(&n);
      }
      if (free.empty()) continue;
      const double each =
          (mean * static_cast<double>(e.nodes().size()) - known) / static_cast<double>(free.size());
      if (!std::isfinite(each) || each <= 0.0) continue; // the nodes start as the kernel says
      for (NodeSpec* n : free)
        n->T0 = each;
    }
  } catch (const CsvError&) {
    // reported where the data statement is checked
  }
}

void Elaborator::warn_data_beyond_duration(const CaseSettings& s) {
  const std::size_t after = rows_after(data_times_->table, *s.duration);
  if (after == 0) return;
  report(DiagnosticEngine::make(
      DiagId::data_beyond_duration, data_times_->at, data_times_->mark,
      fs::path(s.data_path).filename().string(),
      after == 1 ? std::string("1 row") : fmt::format("{} rows", after), s.name,
      fmt::format("{:g} s; last row at {:g} s", *s.duration, data_times_->table.time().back()),
      after == 1 ? "it is" : "they are"));
}

} // namespace thermnet::lang
