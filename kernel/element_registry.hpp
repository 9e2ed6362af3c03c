#pragma once
/// The registry of element kinds: each plugin contributes a schema and a factory.

#include "kernel/element.hpp"
#include "lang/schema.hpp"

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

namespace thermnet {

/// An element kind: the schema the linter checks against, and how to build its physics.
struct ElementPlugin {
  lang::ElementSchema schema; ///< keys, units, ranges, docs
  /// Builds the element from its evaluated spec (node indices and SI values).
  std::function<std::unique_ptr<Element>(const lang::ElementSpec&)> create;
};

/// Thrown when a plugin cannot be registered (e.g. a duplicate kind name).
struct RegistryError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// All known element kinds; the global instance holds the core kinds and loaded plugins.
class ElementRegistry final : public lang::ElementCatalog {
public:
  /// The process-wide registry.
  static ElementRegistry& global();
  /// Adds a kind; throws RegistryError if the name is taken or the plugin is incomplete.
  void add(ElementPlugin plugin);
  /// The plugin of a kind, or nullptr.
  const ElementPlugin* plugin(std::string_view kind) const;
  const lang::ElementSchema* find(std::string_view kind) const override;
  std::vector<std::string> kinds() const override;

private:
  std::map<std::string, ElementPlugin, std::less<>> plugins_;
  mutable std::mutex mutex_;
};

/// Registers a plugin with the global registry at static-initialisation time (one line per plugin).
struct ElementRegistrar {
  /// Adds the plugin built by `make` to the global registry.
  explicit ElementRegistrar(ElementPlugin (*make)()) { ElementRegistry::global().add(make()); }
};

/// Builds the plugin of a linear kind: its element is a LinearLink with the schema's conductance.
ElementPlugin linear_plugin(lang::ElementSchema schema);

/// A key description for schemas: name, dimension, doc; chain the setters for the rest.
struct Key {
  lang::KeySchema k; ///< the schema being built
  /// A key with a name, dimension and doc.
  Key(std::string name, lang::Dimension dim, std::string doc) {
    k.name = std::move(name);
    k.dim = dim;
    k.doc = std::move(doc);
  }
  /// Marks the key required.
  Key& required() {
    k.required = true;
    return *this;
  }
  /// Gives a default SI value.
  Key& otherwise(double v) {
    k.default_value = v;
    return *this;
  }
  /// Requires value > 0.
  Key& positive() {
    k.min = 0.0;
    k.min_exclusive = true;
    return *this;
  }
  /// Requires value >= 0.
  Key& non_negative() {
    k.min = 0.0;
    k.min_exclusive = false;
    return *this;
  }
  /// Requires value in (0, 1].
  Key& fraction() {
    positive();
    k.max = 1.0;
    return *this;
  }
  /// An optional key that belongs to the alternative group holding `key`.
  Key& goes_with(std::string key) {
    k.with = std::move(key);
    return *this;
  }
  /// Accepts time signals.
  Key& signal() {
    k.type = lang::KeyType::signal;
    return *this;
  }
  /// Takes a node name.
  Key& node() {
    k.type = lang::KeyType::node;
    return *this;
  }
  /// An absolute temperature (bare numbers in degC).
  Key& absolute_temperature() {
    k.absolute_temperature = true;
    k.min = 0.0;
    k.min_exclusive = true;
    return *this;
  }
  /// The finished schema entry.
  operator lang::KeySchema() const { return k; }
};

/// Registers the plugin made by FACTORY (a function returning ElementPlugin) with the global
/// registry.
#define THERMNET_REGISTER_ELEMENT(FACTORY)                                                         \
  static const ::thermnet::ElementRegistrar thermnet_registrar_##FACTORY {                         \
    &FACTORY                                                                                       \
  }

} // namespace thermnet
