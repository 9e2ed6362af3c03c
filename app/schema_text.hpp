#pragma once
/// Markdown descriptions of element kinds, their keys and the built-in statement keys.

#include "lang/model.hpp"
#include "lang/schema.hpp"

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace thermnet::app {

/// A kind's doc, terminals and key table.
std::string kind_markdown(const lang::ElementSchema& s);

/// One key of a kind: doc, unit, default or required, valid range.
std::string key_markdown(const lang::ElementSchema& s, const lang::KeySchema& k);

/// The unit of a key as `thermnet kinds` prints it ("W/K", "degC", "node", ...).
std::string key_unit(const lang::KeySchema& k);

/// A key's default value, or "required" / "optional".
std::string key_default(const lang::KeySchema& k);

/// The markdown table of a kind's keys: unit, default, valid range, description.
std::string key_table_markdown(const lang::ElementSchema& s);

/// A kind's alternative key groups as text ("GR, or A + eps1 + eps2"); empty when it has none.
std::string alternatives_text(const lang::ElementSchema& s);

/// Keys of the built-in statements "node", "boundary" and "case": (name, one-line doc).
const std::vector<std::pair<std::string, std::string>>& builtin_keys(std::string_view statement);

/// The kind of the element named `name` in a model (plugin kind, "series"/"parallel"), or "".
std::string element_kind(const lang::Model& m, std::string_view name);

/// The node or boundary declaration named `name`, or nullptr.
const lang::NodeDecl* find_node(const lang::Model& m, std::string_view name);

} // namespace thermnet::app
