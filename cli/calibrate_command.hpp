#pragma once
/// `thermnet calibrate`: fit the ranged params of a model to the measured data of its cases.

#include <CLI/CLI.hpp>

namespace thermnet::cli {

/// Registers the calibrate subcommand; its exit status is stored in `status`.
/// Exit 0 on success; 1 when nothing can be calibrated, no sample is accepted, or the run was
/// interrupted by Ctrl-C (the best result so far is still written); 2 for usage errors and
/// unwritable outputs.
void add_calibrate_command(CLI::App& app, int& status);

} // namespace thermnet::cli
