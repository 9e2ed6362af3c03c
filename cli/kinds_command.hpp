#pragma once
/// `thermnet kinds [KIND...] [--format text|markdown]`: the element kinds and their key schemas.

#include <CLI/CLI.hpp>

namespace thermnet::cli {

/// Adds the kinds subcommand; its callback stores the exit status in `status`.
void add_kinds_command(CLI::App& app, int& status);

} // namespace thermnet::cli
