#pragma once
/// `thermnet invert` (data-only inverse methods, e.g. TIM-AB) and `thermnet estimate` (state
/// estimation over a model, e.g. the extended Kalman filter): CSV in, CSV of estimates out, or a
/// row-by-row stream on standard input/output with --stream.

#include <CLI/CLI.hpp>

namespace thermnet::cli {

/// Adds the invert and estimate subcommands; their callbacks store the exit status in `status`.
void add_estimate_commands(CLI::App& app, int& status);

} // namespace thermnet::cli
