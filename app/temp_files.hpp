#pragma once
/// Temporary output files that a signal must not leave behind: a fixed table of paths that the
/// handlers of SIGTERM, SIGINT, SIGHUP and SIGPIPE unlink (async-signal-safe) before the signal
/// takes its usual course.

#include <string>

namespace thermnet::app {

/// Installs the handlers once (later calls do nothing); a signal the process ignores stays
/// ignored. The handler unlinks every registered path, restores the default action and raises
/// the signal again, so the process still ends by that signal.
void install_temp_file_cleanup();

/// Registers a temporary file for removal on a signal; returns its slot, or -1 when the table is
/// full or the path too long (the file is then still removed on normal exits and errors).
int register_temp_file(const std::string& path);

/// Forgets a slot of register_temp_file() (after its file was renamed or removed); -1 is ignored.
void unregister_temp_file(int slot);

/// The number of paths registered now (for tests).
int registered_temp_files();

} // namespace thermnet::app
