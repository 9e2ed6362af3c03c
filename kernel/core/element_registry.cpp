#include "kernel/core/element_registry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

namespace thermnet {

void PluginTraits<ElementPlugin>::check(const ElementPlugin& p) {
  const std::string& kind = p.schema.kind;
  const auto word = [](unsigned char c) { return std::isalnum(c) || c == '_'; };
  if (std::isdigit(static_cast<unsigned char>(kind[0])) ||
      !std::all_of(kind.begin(), kind.end(), word))
    throw RegistryError(fmt::format("element kind '{}' is not a name a model can write "
                                    "(letters, digits and '_', not starting with a digit)",
                                    kind));
  if (p.schema.terminals < 1 || p.schema.terminals > 2)
    throw RegistryError(fmt::format("element kind '{}' must have 1 or 2 terminals", p.schema.kind));
  static const char* reserved[] = {"model", "include",  "plugin", "const",    "param",
                                   "node",  "boundary", "series", "parallel", "case"};
  for (const char* r : reserved)
    if (p.schema.kind == r)
      throw RegistryError(
          fmt::format("'{}' is a statement keyword, not a kind name", p.schema.kind));
}

const lang::ElementSchema* ElementCatalogView::find(std::string_view kind) const {
  const ElementPlugin* p = registry_->find(kind);
  return p ? &p->schema : nullptr;
}

const lang::ElementCatalog& element_catalog() {
  static const ElementCatalogView view(ElementRegistry::global());
  return view;
}

ElementPlugin linear_plugin(lang::ElementSchema schema) {
  auto G = schema.conductance;
  return ElementPlugin{
      std::move(schema), [G](const lang::ElementSpec& s) -> std::unique_ptr<Element> {
        return std::make_unique<LinearLink>(s.nodes()[0], s.nodes()[1], G(s.key_values()));
      }};
}

} // namespace thermnet
