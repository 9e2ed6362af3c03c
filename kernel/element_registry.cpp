#include "kernel/element_registry.hpp"

#include <fmt/format.h>

namespace thermnet {

ElementRegistry& ElementRegistry::global() {
  static ElementRegistry registry;
  return registry;
}

void ElementRegistry::add(ElementPlugin plugin) {
  std::lock_guard lock(mutex_);
  const std::string kind = plugin.schema.kind;
  if (kind.empty() || !plugin.create)
    throw RegistryError(fmt::format("element plugin '{}' has no kind name or no factory", kind));
  if (plugin.schema.terminals < 1 || plugin.schema.terminals > 2)
    throw RegistryError(fmt::format("element kind '{}' must have 1 or 2 terminals", kind));
  static const char* reserved[] = {"model", "include",  "plugin", "const",    "param",
                                   "node",  "boundary", "series", "parallel", "case"};
  for (const char* r : reserved)
    if (kind == r)
      throw RegistryError(fmt::format("'{}' is a statement keyword, not a kind name", kind));
  if (plugins_.count(kind))
    throw RegistryError(fmt::format("element kind '{}' is already registered", kind));
  plugins_.emplace(kind, std::move(plugin));
}

const ElementPlugin* ElementRegistry::plugin(std::string_view kind) const {
  std::lock_guard lock(mutex_);
  auto it = plugins_.find(kind);
  return it == plugins_.end() ? nullptr : &it->second;
}

const lang::ElementSchema* ElementRegistry::find(std::string_view kind) const {
  const ElementPlugin* p = plugin(kind);
  return p ? &p->schema : nullptr;
}

std::vector<std::string> ElementRegistry::kinds() const {
  std::lock_guard lock(mutex_);
  std::vector<std::string> out;
  for (const auto& [k, p] : plugins_)
    out.push_back(k);
  return out;
}

ElementPlugin linear_plugin(lang::ElementSchema schema) {
  auto G = schema.conductance;
  return ElementPlugin{
      std::move(schema), [G](const lang::ElementSpec& s) -> std::unique_ptr<Element> {
        return std::make_unique<LinearLink>(s.nodes.at(0), s.nodes.at(1), G(s.key_values()));
      }};
}

} // namespace thermnet
