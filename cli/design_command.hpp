#pragma once
/// `thermnet design MODEL [--param NAME ...] [--case NAME ...] [--objective energy|power]
/// [--samples N] [--evaluations N] [--seed S] [--threads N] [-o DESIGNED.tnet] [--json REPORT.json]
/// [--plot OUT.svg]`: chooses the ranged params (heater powers, set points, ...) so that every
/// requirement is met at the least energy or installed power; exit 1 when none meets them.

#include <CLI/CLI.hpp>

namespace thermnet::cli {

/// Adds the design subcommand; its callback stores the exit status in `status`.
void add_design_command(CLI::App& app, int& status);

} // namespace thermnet::cli
