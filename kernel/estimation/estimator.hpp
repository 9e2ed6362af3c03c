#pragma once
/// Estimator plugins: inverse methods that turn measured columns into estimates of what cannot be
/// measured (TIM-AB surface temperature, Kalman state estimation of a network).
///
/// An estimator is a stream processor: it is told the input columns once, then receives rows one
/// at a time and answers with the estimate rows it has completed. Batch-only work (a full-time-
/// domain fit, a smoother's backward pass) is returned by finish(). The same object therefore
/// serves `--stream` (one output row per input row) and whole-file runs.

#include "kernel/core/registry.hpp"
#include "lang/network_spec.hpp"

#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace thermnet {

/// Wrong settings or data for an estimator (a column that is missing, a window longer than the
/// record, a model the method cannot handle).
struct EstimatorError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// One documented setting of an estimator: name, default (as text, empty: none) and a doc line.
struct EstimatorOption {
  std::string name;          ///< key, e.g. "eta"
  std::string default_value; ///< default as text ("" when the option has no default)
  std::string doc;           ///< one line for --help and the docs
};

/// Settings given to an estimator: text values by option name, with typed accessors.
class EstimatorSettings {
public:
  /// Sets an option (text as typed on the command line).
  void set(const std::string& name, std::string value) { values_[name] = std::move(value); }
  /// True when the option was given.
  bool has(const std::string& name) const { return values_.count(name) != 0; }
  /// The text of an option, or `fallback`.
  std::string text(const std::string& name, const std::string& fallback = "") const;
  /// A number; throws EstimatorError naming the option when the text is not a finite number.
  double number(const std::string& name, double fallback) const;
  /// A comma-separated list of names (empty entries dropped; commas inside brackets, as in
  /// `p[1,2]`, belong to the name).
  std::vector<std::string> list(const std::string& name) const;
  /// A yes/no flag ("1", "true", "yes" are true).
  bool flag(const std::string& name) const;
  /// Every option given, by name.
  const std::map<std::string, std::string>& values() const { return values_; }

private:
  std::map<std::string, std::string> values_;
};

/// What an estimator knows before the first row.
struct EstimatorContext {
  std::vector<std::string> columns;           ///< input columns, columns[0] == "time"
  const lang::NetworkSpec* network = nullptr; ///< the model (model-based estimators), else null
  EstimatorSettings settings;                 ///< the method's options
};

/// One output row: a time and one value per output column (NaN: no estimate yet).
struct EstimateRow {
  double time = 0.0;          ///< s
  std::vector<double> values; ///< in the order of Estimator::output_columns()
};

/// A summary figure of a run, e.g. {"rmse_A", 0.42, "K"}; printed and written to --json.
struct EstimateMetric {
  std::string name; ///< identifier, e.g. "mean_relative_error"
  double value;     ///< value in `unit`
  std::string unit; ///< unit text ("%", "K", "s", "" for counts)
};

/// An inverse method working on a stream of rows.
class Estimator {
public:
  virtual ~Estimator() = default;
  /// Names of the output columns after `time` (degC temperatures unless the name says otherwise).
  virtual std::vector<std::string> output_columns() const = 0;
  /// Takes the next input row (values in the order of EstimatorContext::columns, time first,
  /// NaN for missing cells) and returns the rows it completes (streaming methods: one per row).
  virtual std::vector<EstimateRow> push(const std::vector<double>& row) = 0;
  /// Ends the input and returns the rows not returned yet (batch methods return everything here).
  virtual std::vector<EstimateRow> finish() = 0;
  /// Figures of merit of the run so far (errors against true columns, compute time per step).
  virtual std::vector<EstimateMetric> metrics() const { return {}; }
};

/// A named estimator kind with a doc line, its options and a factory.
struct EstimatorPlugin {
  static constexpr const char* family = "estimator"; ///< registry family name
  std::string name;                                  ///< e.g. "tim-ab"
  std::string doc;                                   ///< one line for --help
  bool needs_model = false;                          ///< true: the context must carry a network
  std::vector<EstimatorOption> options;              ///< documented settings
  /// Builds an estimator; throws EstimatorError on bad settings or columns.
  std::function<std::unique_ptr<Estimator>(const EstimatorContext&)> create;
};

/// All estimator kinds.
using EstimatorRegistry = Registry<EstimatorPlugin>;

/// Index of a named input column, or throws EstimatorError naming `what` and the columns present.
int require_column(const std::vector<std::string>& columns, const std::string& name,
                   const std::string& what);

} // namespace thermnet
