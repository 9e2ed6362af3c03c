// Finding and loading libthermnet_pagmo_sga (plugins/optimizer/pagmo_sga.hpp) and its entry points.
// It is looked for, in order, where an installation puts it relative to the binary holding this
// code (the executable or the Python module), beside that binary, and where the build tree made it.

#include "plugins/optimizer/pagmo_sga.hpp"

#include <dlfcn.h>
#include <fmt/format.h>

#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace thermnet {
namespace {

/// The directory of the binary this code was linked into (empty if unknown).
std::filesystem::path own_directory() {
  Dl_info info{};
  if (::dladdr(reinterpret_cast<void*>(&load_pagmo_sga), &info) == 0 || !info.dli_fname) return {};
  std::error_code ec;
  auto path = std::filesystem::canonical(info.dli_fname, ec);
  return ec ? std::filesystem::path{} : path.parent_path();
}

/// Candidate paths of the library, in the order they are tried.
std::vector<std::filesystem::path> candidates() {
  const std::filesystem::path name = THERMNET_PAGMO_SGA_FILE_NAME;
  std::vector<std::filesystem::path> paths;
  if (const auto dir = own_directory(); !dir.empty()) {
    paths.push_back(dir / THERMNET_PAGMO_SGA_INSTALL_RELATIVE_DIR / name);
    paths.push_back(dir / name);
  }
  paths.push_back(THERMNET_PAGMO_SGA_BUILD_PATH);
  return paths;
}

// The library, loaded once per process (RTLD_LOCAL: its pagmo stays its own).
void* load_library() {
  std::string tried;
  for (const auto& path : candidates()) {
    if (void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL)) return handle;
    const char* why = ::dlerror(); // names the path already
    tried += fmt::format("{}{}", tried.empty() ? "" : "; ", why ? why : path.string());
  }
  throw std::runtime_error("pagmo's algorithms ('ga', `design`) need " THERMNET_PAGMO_SGA_FILE_NAME
                           ", which could not be loaded: " +
                           tried);
}

// The library's entry point `name`.
void* entry_point(const char* name) {
  static std::mutex mutex;
  static void* handle = nullptr;
  std::lock_guard<std::mutex> lock(mutex);
  if (!handle) handle = load_library();
  if (void* entry = ::dlsym(handle, name)) return entry;
  throw std::runtime_error(
      fmt::format("{} has no entry point {}", THERMNET_PAGMO_SGA_FILE_NAME, name));
}

} // namespace

SgaEvolve load_pagmo_sga() {
  return reinterpret_cast<SgaEvolve>(entry_point("thermnet_pagmo_sga_evolve"));
}

CompassSearch load_pagmo_compass() {
  return reinterpret_cast<CompassSearch>(entry_point("thermnet_pagmo_compass_search"));
}

} // namespace thermnet
