#include "app/output_stream.hpp"

#include "app/temp_files.hpp"
#include "kernel/core/process_group.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <iostream>
#include <poll.h>
#include <streambuf>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace thermnet::app {
namespace {

namespace fs = std::filesystem;

/// Bytes gathered before a write() call.
constexpr std::size_t kBufferSize = 1 << 18;
/// Most bytes of the target's name kept in its temporary file's name.
constexpr std::size_t kMaxLeaf = 200;

/// The permission bits a new file gets (0666 without the umask), as open(O_CREAT) would give.
mode_t new_file_mode() {
  static const mode_t mode = [] {
    const mode_t mask = ::umask(0);
    ::umask(mask);
    return static_cast<mode_t>(0666 & ~mask);
  }();
  return mode;
}

/// Writes all of [p, p + n) to fd (retrying interrupted and partial writes); 0 or an errno.
int write_all(int fd, const char* p, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) { // a non-blocking descriptor: wait for room
        pollfd pfd{fd, POLLOUT, 0};
        ::poll(&pfd, 1, -1);
        continue;
      }
      return errno;
    }
    p += w;
    n -= static_cast<std::size_t>(w);
  }
  return 0;
}

/// std::cout's buffer once route_standard_output() ran: writes go to descriptor 1 and the first
/// failure's errno is kept (stdio forgets it: later calls overwrite errno before anyone asks).
class StandardOutputBuffer final : public std::streambuf {
public:
  StandardOutputBuffer() : buffer_(kBufferSize) { reset(); }
  /// The errno of the first failed write, or 0.
  int error() const { return error_; }

protected:
  int_type overflow(int_type ch) override {
    if (sync() != 0) return traits_type::eof();
    if (!traits_type::eq_int_type(ch, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(ch);
      pbump(1);
    }
    return traits_type::not_eof(ch);
  }
  int sync() override {
    const auto n = static_cast<std::size_t>(pptr() - pbase());
    const int err = n > 0 ? write_all(STDOUT_FILENO, pbase(), n) : 0;
    reset();
    if (err != 0 && error_ == 0) error_ = err;
    return err == 0 ? 0 : -1;
  }

private:
  void reset() { setp(buffer_.data(), buffer_.data() + buffer_.size()); }
  std::vector<char> buffer_;
  int error_ = 0;
};

/// The buffer installed by route_standard_output(), or null.
StandardOutputBuffer* g_standard_output = nullptr;

} // namespace

void route_standard_output() {
  if (g_standard_output) return;
  std::cout.flush();
  std::fflush(stdout);
  // Never freed: std::cout is flushed once more while static objects are destroyed.
  g_standard_output = new StandardOutputBuffer;
  std::cout.rdbuf(g_standard_output);
  if (::isatty(STDOUT_FILENO)) std::cout.setf(std::ios::unitbuf); // a terminal sees each line
}

OutputStream::OutputStream()
    : name_("standard output"), standard_output_(true), fd_(STDOUT_FILENO) {
  flush_standard_output(); // what the command printed before comes first
  buffer_.reserve(kBufferSize);
}

namespace {

/// Under mpirun every rank holds the same result: rank 0 alone writes it (docs/cluster.md); the
/// other ranks write to /dev/null.
std::string this_ranks_target(const std::string& path) {
  return process_group().rank() == 0 ? path : "/dev/null";
}

} // namespace

OutputStream::OutputStream(const std::string& path, Follow follow)
    : name_(path),
      target_(resolve_output(this_ranks_target(path),
                             this_ranks_target(path) == path ? follow : Follow::symlinks)) {
  buffer_.reserve(kBufferSize);
  if (target_.kind == OutputTarget::Kind::stream) {
    fd_ = ::open(target_.real.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
    if (fd_ < 0) fail("open", errno);
    return;
  }
  install_temp_file_cleanup();
  const fs::path real(target_.real);
  // A leading dot hides it; the name is cut so that the suffix fits in NAME_MAX.
  const std::string leaf = real.filename().string().substr(0, kMaxLeaf);
  temp_ = (real.parent_path() / fmt::format(".{}.tmp.XXXXXX", leaf)).string();
  fd_ = ::mkostemp(temp_.data(), O_CLOEXEC);
  if (fd_ < 0) {
    const int err = errno;
    temp_.clear();
    fail("create a temporary file", err);
  }
  temp_slot_ = register_temp_file(temp_);
}

OutputStream::~OutputStream() {
  if (!published_) discard();
}

void OutputStream::discard() noexcept {
  if (fd_ >= 0 && !standard_output_) ::close(fd_);
  fd_ = -1;
  if (!temp_.empty()) ::unlink(temp_.c_str());
  unregister_temp_file(temp_slot_);
  temp_slot_ = -1;
  temp_.clear();
}

void OutputStream::fail(const char* what, int err) {
  discard();
  published_ = true; // nothing left to remove
  if (standard_output_)
    throw OutputError(fmt::format("cannot write to standard output: {}", std::strerror(err)));
  throw OutputError(fmt::format("cannot write '{}': {} ({})", name_, std::strerror(err), what));
}

void OutputStream::write(std::string_view text) {
  if (fd_ < 0) throw OutputError(fmt::format("'{}' was already closed", name_));
  buffer_.append(text);
  if (buffer_.size() >= kBufferSize) flush_buffer();
}

void OutputStream::flush_buffer() {
  if (const int err = write_all(fd_, buffer_.data(), buffer_.size())) fail("write", err);
  buffer_.clear();
}

void OutputStream::finish() {
  if (fd_ < 0) return;
  flush_buffer();
  if (standard_output_) {
    fd_ = -1;
    return;
  }
  if (!temp_.empty()) {
    const mode_t mode =
        target_.kind == OutputTarget::Kind::regular_file ? target_.mode : new_file_mode();
    if (::fchmod(fd_, mode) != 0) fail("chmod", errno);
    if (::fsync(fd_) != 0) fail("sync", errno);
  }
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail("close", errno);
}

void OutputStream::publish() {
  if (temp_.empty() || published_) return;
  struct stat st {};
  if (::lstat(target_.real.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    discard();
    published_ = true;
    throw OutputError(
        fmt::format("cannot write '{}': '{}' is no longer a regular file; it was not replaced",
                    name_, target_.real));
  }
  if (std::rename(temp_.c_str(), target_.real.c_str()) != 0) fail("rename", errno);
  unregister_temp_file(temp_slot_);
  temp_slot_ = -1;
  temp_.clear();
  published_ = true;
}

std::unique_ptr<OutputStream> open_output(const std::string& path) {
  return path.empty() ? std::make_unique<OutputStream>() : std::make_unique<OutputStream>(path);
}

void commit(const std::vector<OutputStream*>& outputs) {
  for (OutputStream* o : outputs)
    if (o) o->finish();
  for (OutputStream* o : outputs)
    if (o) o->publish();
}

void flush_standard_output() {
  errno = 0;
  std::cout.flush();
  bool failed = !std::cout;
  int err = g_standard_output ? g_standard_output->error() : (failed ? errno : 0);
  if (std::fflush(stdout) != 0) {
    failed = true;
    if (err == 0) err = errno;
  }
  if (!failed && !std::ferror(stdout)) return;
  std::clearerr(stdout);
  std::cout.clear();
  throw OutputError(fmt::format("cannot write to standard output: {}",
                                err != 0 ? std::strerror(err) : "a write failed"));
}

} // namespace thermnet::app
