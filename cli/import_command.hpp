#pragma once
/// `thermnet import FILE... [-o MODEL.tnet] [--format sinda|spice] [--allow-partial]`: SINDA/FLUINT
/// decks and SPICE netlists as a thermnet model (docs/import.md).

#include <CLI/CLI.hpp>

namespace thermnet::cli {

/// Adds the import subcommand; its callback stores the exit status in `status`.
void add_import_command(CLI::App& app, int& status);

} // namespace thermnet::cli
