// The path policy: model-named files stay in the model's folder tree and are regular files.

#include "lang/path_policy.hpp"

#include "lang/display_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <linux/magic.h>
#include <mutex>
#include <string_view>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>
#include <vector>

namespace thermnet::lang {

namespace fs = std::filesystem;

namespace {

std::mutex g_policy_mutex; // the policy may be read by worker threads while a caller sets it
PathPolicy g_policy;
bool g_allow_outside = false;
std::vector<fs::path> g_named; // canonical paths the user named on the command line

/// The canonical form of a path (symlinks resolved), or the path itself if it cannot be formed.
fs::path canonical_or_self(const std::string& path) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return ec ? fs::path(path) : c;
}

/// Whether `p` lies inside the folder `root` (both canonical).
bool inside(const fs::path& p, const fs::path& root) {
  auto r = root.begin();
  auto q = p.begin();
  for (; r != root.end(); ++r, ++q) {
    if (r->empty()) continue; // a trailing separator
    if (q == p.end() || *q != *r) return false;
  }
  return true;
}

/// What a file that is not a regular file is, for the message.
std::string kind_of(mode_t mode) {
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

/// Whether a file system holds kernel interfaces rather than files (/proc, /sys, ...).
bool pseudo_file_system(long type) {
  switch (type) {
  case PROC_SUPER_MAGIC:
  case SYSFS_MAGIC:
  case DEBUGFS_MAGIC:
  case TRACEFS_MAGIC:
  case SECURITYFS_MAGIC:
  case CGROUP_SUPER_MAGIC:
  case CGROUP2_SUPER_MAGIC:
    return true;
  default:
    return false;
  }
}

} // namespace

void set_path_policy(PathPolicy policy) {
  std::lock_guard lock(g_policy_mutex);
  g_policy = std::move(policy);
}

PathPolicy path_policy() {
  std::lock_guard lock(g_policy_mutex);
  return g_policy;
}

void set_allow_outside_paths(bool allow) {
  g_allow_outside = allow;
}

PathPolicy policy_for_model(const std::string& model_path) {
  const char* env = std::getenv("THERMNET_ALLOW_OUTSIDE_PATHS");
  PathPolicy p;
  p.root = canonical_or_self(model_path).parent_path();
  p.allow_outside = g_allow_outside || (env != nullptr && std::string_view(env) == "1");
  return p;
}

void allow_named_path(const std::string& path) {
  g_named.push_back(canonical_or_self(path));
}

std::optional<std::string> open_model_file(const std::string& path, std::size_t max_bytes, int& fd,
                                           std::size_t& size) {
  fd = -1;
  const fs::path canonical = canonical_or_self(path);
  const bool named = std::find(g_named.begin(), g_named.end(), canonical) != g_named.end();
  const PathPolicy policy = path_policy();
  if (!policy.root.empty() && !policy.allow_outside && !named && !inside(canonical, policy.root))
    return fmt::format("it lies outside the model's folder {}; a model may read only files in "
                       "its own folder tree (pass --allow-outside-paths, or set "
                       "THERMNET_ALLOW_OUTSIDE_PATHS=1, if you trust it)",
                       escape_for_display(policy.root.string()));
  const int f = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (f < 0) return std::string(std::strerror(errno));
  struct stat st {};
  struct statfs sf {};
  std::optional<std::string> problem;
  if (::fstat(f, &st) != 0)
    problem = std::string(std::strerror(errno));
  else if (S_ISDIR(st.st_mode))
    problem = "it is a directory";
  else if (!S_ISREG(st.st_mode))
    problem = fmt::format("it is {}, not a regular file", kind_of(st.st_mode));
  else if (::fstatfs(f, &sf) == 0 && pseudo_file_system(static_cast<long>(sf.f_type)))
    problem = "it is a kernel interface (/proc, /sys), not a file";
  else if (static_cast<std::uintmax_t>(st.st_size) > max_bytes)
    problem = fmt::format("it is larger than {} ({} bytes)",
                          max_bytes == (std::size_t{1} << 30) ? std::string("1 GiB")
                                                              : fmt::format("{} bytes", max_bytes),
                          st.st_size);
  if (problem) {
    ::close(f);
    return problem;
  }
  // Reads block again (a regular file never waits anyway).
  ::fcntl(f, F_SETFL, ::fcntl(f, F_GETFL) & ~O_NONBLOCK);
  fd = f;
  size = static_cast<std::size_t>(st.st_size);
  return std::nullopt;
}

} // namespace thermnet::lang
