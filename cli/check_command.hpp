#pragma once
/// `thermnet check MODEL [--case NAME ...] [--set NAME=VALUE ...] [--json REPORT.json]`: runs the
/// cases and checks the model's requirements (`require ...`); exit 1 when one is violated.

#include <CLI/CLI.hpp>

namespace thermnet::cli {

/// Adds the check subcommand; its callback stores the exit status in `status`.
void add_check_command(CLI::App& app, int& status);

} // namespace thermnet::cli
