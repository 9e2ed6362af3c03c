#pragma once
/// Writing outputs atomically: a temporary file beside the target, then a rename.

#include <stdexcept>
#include <string>
#include <vector>

namespace thermnet::cli {

/// An output that cannot be written (exit status 2).
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A file to write: where, and its whole content.
struct OutputFile {
  std::string path;    ///< target path
  std::string content; ///< the file's content
};

/// Replaces `path` with `content` atomically (temp file + fsync + rename); throws OutputError.
void write_file_atomically(const std::string& path, const std::string& content);

/// Writes several files as one unit: each content goes to a temporary file beside its target
/// (fsync'ed), and only when every one is staged are they renamed into place; a failure while
/// staging (unwritable place, a directory or a repeated path as target) leaves every target
/// untouched and no temporary file behind. Throws OutputError.
void write_files_atomically(const std::vector<OutputFile>& files);

} // namespace thermnet::cli
