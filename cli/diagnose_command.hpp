#pragma once
/// `thermnet diagnose`: what the simulation gets wrong, the cause, the extension and the gain.

#include <CLI/CLI.hpp>

namespace thermnet::cli {

/// Registers the diagnose subcommand; its exit status is stored in `status` (0 when the diagnosis
/// ran, whatever it found; 1 for a model or data problem; 2 for usage errors and unwritable
/// outputs).
void add_diagnose_command(CLI::App& app, int& status);

} // namespace thermnet::cli
