#pragma once
/// The command line of this run, as the user typed it, and the facts a report page names (the
/// program's version, the date).

#include <string>

namespace thermnet::app {

/// Remembers the arguments of this run (called once by run_app).
void remember_command_line(int argc, char** argv);

/// The remembered command line, each argument quoted for a POSIX shell where it needs it
/// ("thermnet" when none was remembered).
std::string command_line();

/// The date and time of the report in UTC ("2026-11-29 09:41 UTC"); SOURCE_DATE_EPOCH (seconds
/// since 1970), when set, gives it instead of the clock (reproducible reports).
std::string report_date();

} // namespace thermnet::app
