#pragma once
/// A scratch directory for tests that need files on disk (models, data), removed at scope exit.

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace thermnet::test {

/// A fresh directory under the system temp dir, unique per instance (mkdtemp), removed at the end.
struct TempDir {
  std::filesystem::path path; ///< the directory

  /// Creates thermnet_TAG_XXXXXX under the system temp dir.
  explicit TempDir(const std::string& tag = "test") {
    std::string tmpl =
        (std::filesystem::temp_directory_path() / ("thermnet_" + tag + "_XXXXXX")).string();
    if (::mkdtemp(tmpl.data()) == nullptr)
      throw std::runtime_error("cannot create a scratch directory from " + tmpl);
    path = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  /// Writes a file (creating its folders) and returns its path.
  std::string write(const std::string& name, const std::string& text) const {
    std::filesystem::path p = path / name;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
};

} // namespace thermnet::test
