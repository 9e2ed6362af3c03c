#pragma once
/// Writing outputs atomically: a temporary file beside the target, then a rename.

#include <stdexcept>
#include <string>

namespace thermnet::cli {

/// An output that cannot be written (exit status 2).
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Replaces `path` with `content` atomically (temp file + fsync + rename); throws OutputError.
void write_file_atomically(const std::string& path, const std::string& content);

} // namespace thermnet::cli
