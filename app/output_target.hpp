#pragma once
/// Where a path given for an output leads: a new or existing regular file at its real path
/// (symlinks resolved), or a character device or FIFO that is written directly.

#include <stdexcept>
#include <string>
#include <sys/types.h>

namespace thermnet::app {

/// An output that cannot be written, or that would destroy what it must not (exit status 2).
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// What an output path names once every symlink is followed.
struct OutputTarget {
  /// How the output is written there.
  enum class Kind {
    new_file,     ///< nothing is there: a file is created in the real directory
    regular_file, ///< an existing regular file: replaced at its real path (temp file + rename)
    stream        ///< a character device or a FIFO: written directly, never replaced
  };
  Kind kind = Kind::new_file; ///< how it is written
  std::string named;          ///< the path as given
  std::string real;           ///< symlinks resolved (a stream: as given)
  dev_t device = 0;           ///< device of an existing file
  ino_t inode = 0;            ///< inode of an existing file
  mode_t mode = 0;            ///< permission bits of an existing regular file

  /// The same file whatever the path: "device:inode" of an existing file, the real path of a new
  /// one.
  std::string identity() const;
};

/// "device:inode" of the regular file at `path` (symlinks followed), or "" when there is none.
std::string regular_file_identity(const std::string& path);

/// How an output path is taken.
enum class Follow {
  symlinks, ///< the user named it: a symlink there is written through, to what it names
  never     ///< the program chose the name: only a regular file or nothing may be there
};

/// Resolves an output path (following symlinks, also dangling ones, to what they name); throws
/// OutputError for a directory, a block device, a socket, a missing directory or a symlink loop.
/// With Follow::never (a name the user did not give) anything but a regular file or nothing at the
/// path itself (a symlink, a device, a FIFO) is an OutputError too.
OutputTarget resolve_output(const std::string& path, Follow follow = Follow::symlinks);

} // namespace thermnet::app
