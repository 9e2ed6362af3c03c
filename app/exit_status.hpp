#pragma once
/// Exit statuses of the command line contract (shared/spec/cli.md).

namespace thermnet::app {

/// Success (lint: no errors).
inline constexpr int exit_ok = 0;
/// The input is wrong or the operation failed (lint errors, solver failure, data mismatch).
inline constexpr int exit_failure = 1;
/// Usage error, unreadable file, unwritable output.
inline constexpr int exit_usage = 2;

} // namespace thermnet::app
