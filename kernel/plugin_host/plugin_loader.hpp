#pragma once
/// Loading plugin shared libraries: dlopen, ABI check, registration into the global registries.

#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace thermnet {

/// Loads plugins into the process-wide element, optimizer and estimator registries.
class PluginLoader {
public:
  /// The process-wide loader.
  static PluginLoader& global();
  /// Loads the plugin at `path` (loading the same library again does nothing); returns a message
  /// saying what went wrong (missing file, not a plugin, ABI mismatch, duplicate kind), or nothing.
  std::optional<std::string> load(const std::string& path);
  /// Canonical paths of the libraries loaded so far, in load order.
  std::vector<std::string> loaded() const;

private:
  std::optional<std::string> load_locked(const std::string& canonical);
  mutable std::mutex mutex_;
  std::vector<std::string> loaded_;
  /// Which plugin library contributed a kind ("element conductance" -> library path).
  std::map<std::string, std::string> owner_;
};

} // namespace thermnet
