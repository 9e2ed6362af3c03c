#pragma once
/// `thermnet lint MODEL... [--format text|json|sarif] [--werror]`.

#include <CLI/CLI.hpp>

#include <functional>

namespace thermnet::cli {

/// Adds the lint subcommand; its callback stores the exit status in `status`.
void add_lint_command(CLI::App& app, int& status);

} // namespace thermnet::cli
