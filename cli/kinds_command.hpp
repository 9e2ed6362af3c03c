#pragma once
/// `thermnet kinds [KIND...] [--family F] [--format text|markdown]`: every plugin family's kinds.

#include <CLI/CLI.hpp>

namespace thermnet::cli {

/// Adds the kinds subcommand; its callback stores the exit status in `status`.
void add_kinds_command(CLI::App& app, int& status);

} // namespace thermnet::cli
