#pragma once
/// `thermnet sweep MODEL --param NAME=LO..HI:N [--param ...] [-o TABLE.csv] [--plot OUT.svg]`: the
/// case run over a grid of param values, one summary row per grid point.

#include <CLI/CLI.hpp>

namespace thermnet::cli {

/// Adds the sweep subcommand; its callback stores the exit status in `status`.
void add_sweep_command(CLI::App& app, int& status);

} // namespace thermnet::cli
