#pragma once
/// The thermnet command line: every subcommand on one CLI11 application (README.md lists them).

namespace thermnet::cli {

/// Parses the arguments and runs the subcommand; renders every error and returns the exit status
/// once standard output is flushed and closed (what was printed there must have arrived).
int run_app(int argc, char** argv);

} // namespace thermnet::cli
