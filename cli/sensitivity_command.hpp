#pragma once
/// `thermnet sensitivity MODEL [--json REPORT.json] [--elements] [--case NAME] [--threads N]`.

#include "kernel/calibration/sensitivity.hpp"
#include "lang/model.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace thermnet::cli {

/// Adds the sensitivity subcommand; its callback stores the exit status in `status`.
void add_sensitivity_command(CLI::App& app, int& status);

/// The --json report: model, definition, cases, outputs, factors, matrix, ranking, simulations,
/// notes.
nlohmann::json sensitivity_json(const lang::Model& model, const SensitivityReport& r);

} // namespace thermnet::cli
