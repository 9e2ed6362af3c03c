#include "app/output_target.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <optional>
#include <sys/stat.h>
#include <unistd.h>

namespace thermnet::app {
namespace {

namespace fs = std::filesystem;

/// Most symlinks followed for one path (Linux's own limit).
constexpr int kMaxSymlinks = 40;

[[noreturn]] void fail(const std::string& path, const std::string& why) {
  throw OutputError(fmt::format("cannot write '{}': {}", path, why));
}

/// The absolute path with every symlink resolved, or nothing (errno set).
std::optional<std::string> real_path_of(const std::string& path) {
  char* r = ::realpath(path.c_str(), nullptr);
  if (!r) return std::nullopt;
  std::string s(r);
  std::free(r);
  return s;
}

/// The path a chain of symlinks ending in nothing leads to (a dangling symlink is written through,
/// creating the file it names, like cp and shell redirections do).
std::string follow_dangling(const std::string& named) {
  std::string p = named;
  for (int hops = 0;; ++hops) {
    struct stat st {};
    if (::lstat(p.c_str(), &st) != 0) {
      if (errno == ENOENT) return p;
      fail(named, std::strerror(errno));
    }
    if (!S_ISLNK(st.st_mode)) fail(named, "it changed while being examined");
    if (hops == kMaxSymlinks) fail(named, std::strerror(ELOOP));
    std::string target(PATH_MAX, '\0');
    const ssize_t n = ::readlink(p.c_str(), target.data(), target.size());
    if (n < 0) fail(named, std::strerror(errno));
    target.resize(static_cast<std::size_t>(n));
    const fs::path t(target);
    p = t.is_absolute() ? target : (fs::path(p).parent_path() / t).string();
  }
}

/// Refuses an output whose directory cannot take it: a file there is written as a temporary
/// beside it and renamed, so the directory itself must be writable (checked for the effective
/// user, before the run: a diagnosis must not run for minutes and then fail to write its report).
void require_writable_directory(const std::string& named, const std::string& real_dir) {
  if (::faccessat(AT_FDCWD, real_dir.c_str(), W_OK | X_OK, AT_EACCESS) != 0)
    fail(named,
         fmt::format("its folder '{}' cannot be written ({})", real_dir, std::strerror(errno)));
}

/// A file to be created at `path` (which does not exist): its real directory must exist.
OutputTarget new_file(const std::string& named, const std::string& path) {
  const fs::path p(path);
  const std::string leaf = p.filename().string();
  if (leaf.empty() || leaf == "." || leaf == "..") fail(named, "it is a directory");
  const std::string dir = p.parent_path().empty() ? "." : p.parent_path().string();
  const auto real_dir = real_path_of(dir);
  if (!real_dir)
    fail(named, errno == ENOENT ? fmt::format("the directory '{}' does not exist", dir)
                                : std::string(std::strerror(errno)));
  require_writable_directory(named, *real_dir);
  OutputTarget t;
  t.kind = OutputTarget::Kind::new_file;
  t.named = named;
  t.real = (fs::path(*real_dir) / leaf).string();
  return t;
}

std::string file_identity(dev_t device, ino_t inode) {
  return fmt::format("{}:{}", static_cast<unsigned long long>(device),
                     static_cast<unsigned long long>(inode));
}

/// A name the program chose (a copy beside an output): a regular file there is replaced (by a
/// rename, which replaces the directory entry, never what a link names), nothing there is created;
/// anything else is refused, a symlink above all: writing through it would change a file nobody
/// named.
OutputTarget resolve_chosen(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) {
    if (errno != ENOENT) fail(path, std::strerror(errno));
    return new_file(path, path);
  }
  if (S_ISLNK(st.st_mode))
    fail(path, "it is a symbolic link, and this name was not given on the command line: it is "
               "not written through");
  if (S_ISDIR(st.st_mode)) fail(path, "it is a directory");
  if (!S_ISREG(st.st_mode))
    fail(path, "it is not a regular file, and this name was not given on the command line");
  OutputTarget t = new_file(path, path); // the real directory, the name itself
  t.kind = OutputTarget::Kind::regular_file;
  t.device = st.st_dev;
  t.inode = st.st_ino;
  t.mode = st.st_mode & 07777;
  return t;
}

} // namespace

std::string OutputTarget::identity() const {
  return kind == Kind::new_file ? real : file_identity(device, inode);
}

std::string regular_file_identity(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return {};
  return file_identity(st.st_dev, st.st_ino);
}

OutputTarget resolve_output(const std::string& path, Follow follow) {
  if (path.empty()) throw OutputError("an output needs a file name");
  if (follow == Follow::never) return resolve_chosen(path);
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    if (errno != ENOENT) fail(path, std::strerror(errno));
    return new_file(path, follow_dangling(path));
  }
  OutputTarget t;
  t.named = path;
  t.device = st.st_dev;
  t.inode = st.st_ino;
  if (S_ISDIR(st.st_mode)) fail(path, "it is a directory");
  if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) {
    t.kind = OutputTarget::Kind::stream;
    t.real = path;
    return t;
  }
  if (!S_ISREG(st.st_mode))
    fail(path, fmt::format("it is a {}; outputs go to regular files, character devices (such as "
                           "/dev/null) and FIFOs only",
                           S_ISBLK(st.st_mode) ? "block device" : "socket"));
  const auto real = real_path_of(path);
  if (!real) fail(path, std::strerror(errno));
  require_writable_directory(path, fs::path(*real).parent_path().string());
  t.kind = OutputTarget::Kind::regular_file;
  t.real = *real;
  t.mode = st.st_mode & 07777;
  return t;
}

} // namespace thermnet::app
