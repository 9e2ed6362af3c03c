#include "cli/atomic_file.hpp"

#include "kernel/core/process_group.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <set>
#include <sys/stat.h>
#include <unistd.h>

namespace thermnet::cli {

namespace {

namespace fs = std::filesystem;

/// Writes `content` to a fresh temporary file beside `path` (synced) and returns its name.
std::string stage(const std::string& path, const std::string& content) {
  fs::path target(path);
  std::error_code ec;
  if (fs::is_directory(target, ec))
    throw OutputError(fmt::format("cannot write '{}': it is a directory", path));
  fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::string tmpl = (dir / fmt::format(".{}.tmp.XXXXXX", target.filename().string())).string();
  int fd = ::mkstemp(tmpl.data());
  if (fd < 0) throw OutputError(fmt::format("cannot write '{}': {}", path, std::strerror(errno)));
  auto fail = [&](const char* what) {
    int err = errno;
    ::close(fd);
    ::unlink(tmpl.c_str());
    throw OutputError(fmt::format("cannot write '{}': {} ({})", path, std::strerror(err), what));
  };
  const char* p = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail("write");
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::fchmod(fd, 0644) != 0 || ::fsync(fd) != 0) fail("sync");
  if (::close(fd) != 0) {
    int err = errno;
    ::unlink(tmpl.c_str());
    throw OutputError(fmt::format("cannot write '{}': {}", path, std::strerror(err)));
  }
  return tmpl;
}

/// Removes staged temporary files (best effort).
void discard(const std::vector<std::string>& staged, std::size_t from = 0) {
  for (std::size_t i = from; i < staged.size(); ++i)
    ::unlink(staged[i].c_str());
}

} // namespace

void write_file_atomically(const std::string& path, const std::string& content) {
  write_files_atomically({OutputFile{path, content}});
}

void write_files_atomically(const std::vector<OutputFile>& files) {
  // Under mpirun every rank holds the same result: rank 0 alone writes it (docs/cluster.md).
  if (process_group().rank() != 0) return;
  std::set<fs::path> targets;
  for (const auto& f : files) {
    std::error_code ec;
    fs::path key = fs::weakly_canonical(fs::path(f.path), ec);
    if (!targets.insert(ec ? fs::path(f.path) : key).second)
      throw OutputError(fmt::format("'{}' is named for two outputs", f.path));
  }
  std::vector<std::string> staged;
  try {
    for (const auto& f : files)
      staged.push_back(stage(f.path, f.content));
  } catch (...) {
    discard(staged);
    throw;
  }
  for (std::size_t i = 0; i < files.size(); ++i)
    if (std::rename(staged[i].c_str(), files[i].path.c_str()) != 0) {
      int err = errno;
      discard(staged, i);
      throw OutputError(fmt::format("cannot write '{}': {}", files[i].path, std::strerror(err)));
    }
}

} // namespace thermnet::cli
