#pragma once
/// `thermnet simulate MODEL [--case NAME] [--steady] [--duration T] [-o OUT.csv] [--plot OUT.svg]`.

#include <CLI/CLI.hpp>

namespace thermnet::cli {

/// Adds the simulate subcommand; its callback stores the exit status in `status`.
void add_simulate_command(CLI::App& app, int& status);

} // namespace thermnet::cli
