#pragma once
/// `thermnet lsp`: the language server over standard input and output (docs in
/// editors/vscode/README.md).

#include <CLI/CLI.hpp>

namespace thermnet::cli {

/// Adds the lsp subcommand; its callback stores the exit status in `status`.
void add_lsp_command(CLI::App& app, int& status);

} // namespace thermnet::cli
