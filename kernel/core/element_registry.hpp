#pragma once
/// The registry of element kinds: each plugin contributes a schema and a factory.

#include "kernel/core/element.hpp"
#include "kernel/core/registry.hpp"
#include "lang/schema.hpp"

#include <functional>
#include <memory>
#include <string>

namespace thermnet {

/// An element kind: the schema the linter checks against, and how to build its physics.
struct ElementPlugin {
  lang::ElementSchema schema; ///< keys, units, ranges, docs
  /// Builds the element from its evaluated spec (node indices and SI values).
  std::function<std::unique_ptr<Element>(const lang::ElementSpec&)> create;
};

/// How the registry treats element kinds: named by their schema's kind, 1 or 2 terminals, never a
/// statement keyword.
template <> struct PluginTraits<ElementPlugin> {
  static constexpr const char* family = "element"; ///< for messages
  /// The kind name.
  static const std::string& name(const ElementPlugin& p) { return p.schema.kind; }
  /// True when the factory is set.
  static bool has_factory(const ElementPlugin& p) { return static_cast<bool>(p.create); }
  /// Terminal count and keyword checks.
  static void check(const ElementPlugin& p);
};

/// All element kinds.
using ElementRegistry = Registry<ElementPlugin>;

/// The element kinds of a registry as the language sees them: schemas by kind name.
class ElementCatalogView final : public lang::ElementCatalog {
public:
  /// A view of `registry` (which must outlive it).
  explicit ElementCatalogView(const ElementRegistry& registry) : registry_(&registry) {}
  const lang::ElementSchema* find(std::string_view kind) const override;
  std::vector<std::string> kinds() const override { return registry_->names(); }

private:
  const ElementRegistry* registry_;
};

/// The catalog of the global element registry (what Model::load checks elements against).
const lang::ElementCatalog& element_catalog();

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
  /// A temperature difference: a value in degC or degF is scaled, not shifted (0.4 [degC] is 0.4
  /// K).
  Key& temperature_difference() {
    k.temperature_difference = true;
    return *this;
  }
  /// A time constant the element integrates as a state (unresolved_lag(): far too short is none).
  Key& lag() {
    k.lag = true;
    return *this;
  }
  /// The finished schema entry.
  operator lang::KeySchema() const { return k; }
};

} // namespace thermnet
