#include "app/prediction_options.hpp"

#include "app/option_rules.hpp"

#include <CLI/CLI.hpp>

namespace thermnet::app {

void add_prediction_options(CLI::App* cmd, PredictionOptions& o, const std::string& criterion_help,
                            const std::string& plot_help) {
  cmd->add_option("--criterion", o.criterion, criterion_help)
      ->check(CLI::IsMember({"output-error", "prediction"}));
  cmd->add_option("--initial-sd", o.initial_sd,
                  "prediction: standard deviation of the initial states in K (default 1)")
      ->check(rule_validator(positive_number_rule, "NUMBER"));
  cmd->add_option("--whiteness-plot", o.whiteness_plot, plot_help);
}

} // namespace thermnet::app
