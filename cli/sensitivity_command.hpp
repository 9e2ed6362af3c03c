#pragma once
/// `thermnet sensitivity MODEL [--json REPORT.json] [--elements] [--case NAME] [--threads N]`.

#include <CLI/CLI.hpp>

namespace thermnet::cli {

/// Adds the sensitivity subcommand; its callback stores the exit status in `status`.
void add_sensitivity_command(CLI::App& app, int& status);

} // namespace thermnet::cli
