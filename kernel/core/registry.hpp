#pragma once
/// One registry for every plugin family (element kinds, optimizers, estimators, diagnosis
/// hypotheses): kinds by name, one locking rule, one error type, the same name and factory checks.
///
/// A family declares itself by specialising PluginTraits next to its plugin type; a plugin file
/// registers with one line, THERMNET_REGISTER(PluginType, factory). Locking rule: every call takes
/// the registry's mutex; entries are never removed, so a pointer returned by find() stays valid.

#include <fmt/format.h>

#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace thermnet {

/// A plugin that cannot be registered: an empty or taken name, no factory, or a family's own rule.
struct RegistryError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

/// What a registry knows of a plugin family. The default serves plugin types with a `name`, a
/// `create` factory and a `static constexpr const char* family` ("optimizer", ...); a family with
/// other fields or its own rules (element kinds) specialises it beside its plugin type.
template <class Plugin> struct PluginTraits {
  static constexpr const char* family = Plugin::family; ///< for messages
  /// The kind's name.
  static const std::string& name(const Plugin& p) { return p.name; }
  /// True when the factory is set.
  static bool has_factory(const Plugin& p) { return static_cast<bool>(p.create); }
  /// The family's own rules (none by default); throws RegistryError.
  static void check(const Plugin&) {}
};

/// Throws RegistryError unless `plugin` has a usable name, a factory and passes its family's rules.
template <class Plugin> void check_plugin(const Plugin& plugin) {
  using Traits = PluginTraits<Plugin>;
  const std::string& name = Traits::name(plugin);
  if (name.empty() || !Traits::has_factory(plugin))
    throw RegistryError(
        fmt::format("{} plugin '{}' has no kind name or no factory", Traits::family, name));
  for (unsigned char c : name)
    if (c <= ' ' || c >= 0x7f)
      throw RegistryError(fmt::format("{} kind name '{}' must be printable ASCII without spaces",
                                      Traits::family, name));
  Traits::check(plugin);
}

/// The kinds of one plugin family, by name.
template <class Plugin> class Registry {
public:
  /// The process-wide registry of this family (core kinds and loaded plugins).
  static Registry& global();
  /// Adds a kind; throws RegistryError if it is invalid (check_plugin) or its name is taken.
  void add(Plugin plugin);
  /// The plugin of a name, or nullptr.
  const Plugin* find(std::string_view name) const;
  /// All names, sorted.
  std::vector<std::string> names() const;

private:
  std::map<std::string, Plugin, std::less<>> plugins_;
  mutable std::mutex mutex_;
};

template <class Plugin> Registry<Plugin>& Registry<Plugin>::global() {
  static Registry registry;
  return registry;
}

template <class Plugin> void Registry<Plugin>::add(Plugin plugin) {
  check_plugin(plugin);
  std::string name = PluginTraits<Plugin>::name(plugin);
  std::lock_guard lock(mutex_);
  if (plugins_.count(name))
    throw RegistryError(
        fmt::format("{} kind '{}' is already registered", PluginTraits<Plugin>::family, name));
  plugins_.emplace(std::move(name), std::move(plugin));
}

template <class Plugin> const Plugin* Registry<Plugin>::find(std::string_view name) const {
  std::lock_guard lock(mutex_);
  auto it = plugins_.find(name);
  return it == plugins_.end() ? nullptr : &it->second;
}

template <class Plugin> std::vector<std::string> Registry<Plugin>::names() const {
  std::lock_guard lock(mutex_);
  std::vector<std::string> out;
  out.reserve(plugins_.size());
  for (const auto& entry : plugins_)
    out.push_back(entry.first);
  return out;
}

/// Adds a plugin to its family's global registry at static-initialisation time.
template <class Plugin> struct Registrar {
  /// Adds the plugin built by `make`.
  explicit Registrar(Plugin (*make)()) { Registry<Plugin>::global().add(make()); }
};

} // namespace thermnet

/// Registers the plugin of type PLUGIN made by FACTORY (a function returning PLUGIN) with its
/// family's global registry: the one line that ends a plugin file.
#define THERMNET_REGISTER(PLUGIN, FACTORY)                                                         \
  static const ::thermnet::Registrar<PLUGIN> thermnet_registrar_##FACTORY {                        \
    &FACTORY                                                                                       \
  }
