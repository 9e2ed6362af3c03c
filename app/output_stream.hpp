#pragma once
/// Writing one output as it is produced: into a temporary file in the real directory of its target
/// (renamed onto the target only when everything was written), directly into a device or FIFO,
/// or to standard output. Every write, sync and close is checked.

#include "app/output_target.hpp"

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace thermnet::app {

/// An output being written, buffered; an uncommitted temporary file is removed when the stream is
/// destroyed (and, through the temp-file table, when a signal ends the process).
class OutputStream {
public:
  /// Standard output (what was printed there through std::cout before comes first).
  OutputStream();
  /// The output named `path` (see resolve_output; `follow`: how a symlink there is taken): a new
  /// temporary file beside the real target, or the device or FIFO itself opened for writing;
  /// throws OutputError.
  explicit OutputStream(const std::string& path, Follow follow = Follow::symlinks);
  /// Removes the temporary file unless it was published.
  ~OutputStream();
  OutputStream(const OutputStream&) = delete;            ///< not copyable
  OutputStream& operator=(const OutputStream&) = delete; ///< not copyable

  /// Appends text; throws OutputError when the data cannot be written (a full disk, a closed pipe
  /// with SIGPIPE ignored, ...).
  void write(std::string_view text);
  /// Writes what is buffered and, for a temporary file, syncs and closes it; throws OutputError.
  void finish();
  /// Makes a finished temporary file the target (rename; the target must still be a regular file
  /// or nothing); nothing to do for a device, a FIFO or standard output. Throws OutputError.
  void publish();
  /// The path as given, or "standard output".
  const std::string& name() const { return name_; }

private:
  void flush_buffer();
  [[noreturn]] void fail(const char* what, int err);
  void discard() noexcept;

  std::string name_;
  OutputTarget target_;
  bool standard_output_ = false;
  int fd_ = -1;
  std::string temp_;   // the temporary file ("" when writing directly)
  int temp_slot_ = -1; // its slot in the temp-file table
  bool published_ = false;
  std::string buffer_;
};

/// The output named `path`, or standard output when `path` is empty; throws OutputError.
std::unique_ptr<OutputStream> open_output(const std::string& path);

/// Finishes every stream (null ones are skipped), then publishes each: no target is replaced unless
/// every output was written in full. Throws OutputError (the unpublished temporary files are
/// removed).
void commit(const std::vector<OutputStream*>& outputs);

/// Sends std::cout to descriptor 1 through a buffer that keeps the reason of a failed write (for
/// flush_standard_output); a terminal gets each write at once. main() calls it first.
void route_standard_output();

/// Flushes standard output (std::cout and stdio) and checks that everything written there
/// arrived; throws OutputError ("cannot write to standard output: No space left on device").
void flush_standard_output();

} // namespace thermnet::app
