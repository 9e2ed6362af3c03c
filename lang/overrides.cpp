// Values set from outside a model (`--set`): which keys may be set, and checking a set of values
// against every case before a run uses them.

#include "lang/elaborator.hpp"
#include "lang/model.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace thermnet::lang {

const KeySchema& Model::settable_key(std::string_view object, std::string_view key,
                                     const std::string& option) const {
  const ElementSchema* schema = nullptr;
  std::string what;
  if (const int n = node_index(object); n >= 0) {
    schema = nodes_[static_cast<std::size_t>(n)].boundary ? &boundary_schema() : &node_schema();
    what = fmt::format("{} '{}'", schema->kind, object);
  } else if (const int e = element_index(object); e >= 0) {
    const ElementDecl& d = elements_[static_cast<std::size_t>(e)];
    if (d.composite)
      throw OverrideError(fmt::format("{}: the keys of {} '{}' belong to its inner elements and "
                                      "cannot be set",
                                      option, d.composite->mode.name, object));
    if (!d.schema || !d.valid)
      throw OverrideError(fmt::format("{}: element '{}' has errors", option, object));
    schema = d.schema;
    what = fmt::format("{} '{}'", schema->kind, object);
  } else {
    if (const Scope* sc = instance(object))
      throw OverrideError(
          fmt::format("{}: '{}' is an instance of submodel '{}': set a key of one of its elements "
                      "('{}.ELEMENT.KEY') or a param of the model it is given",
                      option, object, sc->submodel->name, object));
    std::vector<std::string> names;
    for (const auto& d : elements_)
      names.emplace_back(d.name);
    for (const auto& d : nodes_)
      names.emplace_back(d.name);
    std::string msg =
        fmt::format("{}: the model has no node, boundary or element '{}'", option, object);
    if (auto s = closest_match(std::string(object), names))
      msg += fmt::format("; did you mean '{}'?", *s);
    throw OverrideError(msg);
  }
  const KeySchema* ks = schema->key(key);
  if (ks && ks->type == KeyType::node)
    throw OverrideError(fmt::format("{}: '{}' of {} names a node: it is part of the wiring and "
                                    "cannot be set",
                                    option, key, what));
  if (ks) return *ks;
  std::vector<std::string> names;
  for (const auto& k : schema->keys)
    if (k.type != KeyType::node) names.push_back(k.name);
  std::string msg = fmt::format("{}: {} has no key '{}'", option, what, key);
  if (auto s = closest_match(std::string(key), names))
    msg += fmt::format("; did you mean '{}'?", *s);
  else
    msg += fmt::format(" ('{}' takes: {})", schema->kind, fmt::join(names, ", "));
  throw OverrideError(msg);
}

void Model::set_overrides(Overrides overrides) {
  {
    std::lock_guard lock(cache_mutex_);
    cache_.clear(); // elaborated without them
  }
  overrides_ = std::move(overrides);
  if (overrides_.empty()) return;
  // Every case takes them, as a model edited to these values would have to.
  for (const auto& name : run_case_names()) {
    try {
      NetworkSpec net = instantiate(name);
      remember(resolve_case(name), std::move(net));
    } catch (const ModelError& e) {
      Diagnostic d = e.diag;
      std::vector<std::string> given = overrides_.param_texts;
      for (const auto& k : overrides_.keys)
        given.push_back(k.option);
      std::string list;
      for (const auto& g : given)
        list += (list.empty() ? "" : ", ") + g;
      d.notes.push_back(DiagnosticEngine::note(DiagId::note_text, std::nullopt,
                                               fmt::format("with the values set by {}", list)));
      throw OverrideError(e.what(), std::move(d));
    }
  }
}

} // namespace thermnet::lang
