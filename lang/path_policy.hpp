#pragma once
/// Which files a model may make thermnet read: a model is untrusted input, so its include, data
/// and table paths stay inside the model's folder tree (unless the user allows more), and never
/// name a FIFO, a device, a socket or a file of /proc or /sys. Files are opened without blocking
/// and their size is checked with fstat before anything is read.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

namespace thermnet::lang {

/// Where the files a model names may lie.
struct PathPolicy {
  std::filesystem::path root; ///< canonical folder of the model; empty: anywhere
  bool allow_outside = false; ///< the user allowed paths outside `root` (--allow-outside-paths)
};

/// Sets the process-wide policy: the command line sets it for the model it loads (root = the
/// model's folder), the language server for each document it analyses.
void set_path_policy(PathPolicy policy);
/// The process-wide policy (default: anywhere).
PathPolicy path_policy();
/// The policy for the model file at `model_path`: its folder is the root; outside paths are
/// allowed when the user passed --allow-outside-paths or set THERMNET_ALLOW_OUTSIDE_PATHS=1.
PathPolicy policy_for_model(const std::string& model_path);
/// Records --allow-outside-paths for policy_for_model().
void set_allow_outside_paths(bool allow);
/// Lets a file the user named on the command line be read wherever it is (still not a FIFO or a
/// device): e.g. the DATA argument of `thermnet estimate`.
void allow_named_path(const std::string& path);

/// Opens `path` for reading under the policy without blocking (O_NONBLOCK: a FIFO cannot hang
/// it) and checks what it is with fstat: a regular file of at most `max_bytes`, not on /proc or
/// /sys. Returns the open descriptor in `fd`, its size in `size`, or an error message.
std::optional<std::string> open_model_file(const std::string& path, std::size_t max_bytes, int& fd,
                                           std::size_t& size);

} // namespace thermnet::lang
