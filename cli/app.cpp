// The thermnet command line: every subcommand on one CLI11 application. Every error is caught
// here and rendered; no input ends in a crash. (In the library, not in main.cpp, so that CLI11 is
// compiled with the commands' batch in a unity build rather than once more for the executable.)

#include "cli/app.hpp"

#include "app/command_line.hpp"
#include "app/exit_status.hpp"
#include "app/model_loading.hpp"
#include "app/output_stream.hpp"
#include "cli/calibrate_command.hpp"
#include "cli/check_command.hpp"
#include "cli/design_command.hpp"
#include "cli/diagnose_command.hpp"
#include "cli/estimate_command.hpp"
#include "cli/import_command.hpp"
#include "cli/kinds_command.hpp"
#include "cli/lint_command.hpp"
#include "cli/lsp_command.hpp"
#include "cli/sensitivity_command.hpp"
#include "cli/simulate_command.hpp"
#include "cli/sweep_command.hpp"
#include "lang/display_text.hpp"

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cstring>
#include <exception>
#include <iostream>
#include <unistd.h>

namespace thermnet::cli {
using namespace app;
namespace {

/// The exit status once standard output is flushed and closed: what was printed there must have
/// arrived (`thermnet lint --format json > /dev/full` fails); a status of 0 becomes 2 otherwise.
int close_standard_output(int status) {
  try {
    flush_standard_output();
  } catch (const OutputError& e) {
    std::cerr << "thermnet: error: " << e.what() << "\n";
    return status != exit_ok ? status : exit_usage;
  }
  // Some file systems report a failed write only when the file is closed.
  if (::close(STDOUT_FILENO) != 0 && errno != EBADF) {
    std::cerr << "thermnet: error: cannot write to standard output: " << std::strerror(errno)
              << "\n";
    return status != exit_ok ? status : exit_usage;
  }
  return status;
}

int parse_and_run(int argc, char** argv) {
  CLI::App app{"thermnet: lumped-parameter thermal networks (lint, simulate, calibrate, diagnose)",
               "thermnet"};
  app.set_version_flag("--version", std::string("thermnet ") + THERMNET_VERSION);
  app.require_subcommand(1);
  int status = exit_ok;
  add_plugin_option(app);
  add_lint_command(app, status);
  add_simulate_command(app, status);
  add_estimate_commands(app, status);
  add_import_command(app, status);
  add_calibrate_command(app, status);
  add_check_command(app, status);
  add_design_command(app, status);
  add_diagnose_command(app, status);
  add_kinds_command(app, status);
  add_lsp_command(app, status);
  add_sensitivity_command(app, status);
  add_sweep_command(app, status);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // As CLI11 prints it, with what the user typed escaped (it may hold control characters).
    std::cerr << thermnet::lang::escape_for_display(e.what())
              << "\nRun with --help for more information.\n";
    return exit_usage;
  } catch (const std::bad_alloc&) {
    std::cerr << "thermnet: error: out of memory\n";
    return exit_failure;
  } catch (const std::exception& e) {
    std::cerr << "thermnet: error: " << thermnet::lang::escape_for_display(e.what()) << "\n";
    return exit_failure;
  }
  return status;
}

} // namespace

int run_app(int argc, char** argv) {
  remember_command_line(argc, argv); // for the report pages (--html)
  return close_standard_output(parse_and_run(argc, argv));
}

} // namespace thermnet::cli
