#pragma once
/// The outputs of a run: checked before it starts (writable, none of them an input or another
/// output) and written all or nothing when their content is known.

#include "app/output_target.hpp"

#include <string>
#include <vector>

namespace thermnet::app {

/// An output file to write: where, and its whole content.
struct OutputFile {
  std::string path;                 ///< target path
  std::string content;              ///< the file's content
  Follow follow = Follow::symlinks; ///< never: a name the program chose (see resolve_output)
};

/// An output of a run as the user named it.
struct NamedOutput {
  std::string option;               ///< the option that names it, e.g. "-o" or "--plot"
  std::string path;                 ///< its path ("" when the option was not given)
  Follow follow = Follow::symlinks; ///< never: a name the program chose (see resolve_output)
};

/// A file a run reads.
struct NamedInput {
  std::string path; ///< its path
  std::string role; ///< what it is, e.g. "the model" or "the data file"
};

/// Checks the outputs of a run before it starts: each can be written where it leads
/// (resolve_output), none is one of the inputs (the same file, however named: symlinks and hard
/// links included) and no two name the same file (a device such as /dev/null may be named
/// several times). Throws OutputError naming both files.
void check_outputs(const std::vector<NamedOutput>& outputs, const std::vector<NamedInput>& inputs);

/// Writes one output (see write_output_files).
void write_output_file(const std::string& path, const std::string& content);

/// Writes several outputs as one unit: each content goes to a temporary file beside its real
/// target (fsync'ed), and only when every one is written are they renamed into place; devices and
/// FIFOs are written directly. A failure (unwritable place, a directory or the same file twice)
/// leaves every regular target untouched and no temporary file behind. Throws OutputError.
void write_output_files(const std::vector<OutputFile>& files);

} // namespace thermnet::app
