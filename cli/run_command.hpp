#pragma once
/// The edge where a command's errors become messages and exit statuses (0 ok, 1 input wrong or
/// operation failed, 2 usage or a file that cannot be read or written).

#include "app/exit_status.hpp"
#include "lang/source.hpp"

#include <functional>
#include <string>

namespace thermnet::cli {

/// What a command does: its work, given the source manager its models load into; returns the
/// exit status.
using CommandBody = std::function<int(lang::SourceManager& sources)>;

/// Runs `body`, then checks that what it printed on standard output arrived (a full disk gives
/// 2), and turns what it throws into a message on stderr and an exit status: a model error is
/// printed compiler-style (report_model_error); every other error as "WHO: error: MESSAGE".
/// Unwritable outputs (also outputs onto inputs or onto each other, and a rewritten model with
/// nowhere to go) and unreadable CSV files give 2;
/// CSV content, solver, network, estimator and diagnosis errors give 1; a `--set` value the model
/// cannot take (lang::OverrideError) gives 2; std::invalid_argument (a bad option or input value)
/// gives `invalid_argument_status`. Anything else is left to main()'s
/// last-resort handler.
int run_command(const std::string& who, const CommandBody& body,
                int invalid_argument_status = app::exit_failure);

} // namespace thermnet::cli
