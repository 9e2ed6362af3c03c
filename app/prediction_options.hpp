#pragma once
/// The options of the prediction criterion (`--criterion`, `--initial-sd`, `--whiteness-plot`),
/// declared with the same rules by every command that compares a model with measurements by it.

#include <string>

namespace CLI {
class App;
} // namespace CLI

namespace thermnet::app {

/// What the three options set.
struct PredictionOptions {
  std::string criterion = "output-error"; ///< "output-error" or "prediction"
  double initial_sd = 1.0;                ///< prediction: initial states' standard deviation, K
  std::string whiteness_plot;             ///< prediction: SVG of the innovations' tests (or empty)
  /// Whether the criterion is the one-step-ahead prediction's likelihood.
  bool prediction() const { return criterion == "prediction"; }
};

/// Declares the three options on `cmd` into `o`; `criterion_help` says what the criterion decides
/// in this command, `plot_help` which innovations the whiteness plot shows.
void add_prediction_options(CLI::App* cmd, PredictionOptions& o, const std::string& criterion_help,
                            const std::string& plot_help);

} // namespace thermnet::app
