#pragma once
/// SPICE parameters in scopes: the netlist's `.param` values, and per subcircuit instance its
/// parameters (given on the X card, evaluated where it stands; the .subckt defaults and the
/// subcircuit's own `.param` values, evaluated inside it). Values are computed when first used;
/// a parameter that depends on itself is an error.

#include "import/spice_cards.hpp"

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace thermnet::importer::spice {

/// A parameter's definition: its expression and where it stands.
struct ParamDef {
  std::string text;         ///< the expression
  lang::FileId file = 0;    ///< its file
  std::uint32_t offset = 0; ///< byte offset of the expression's text in its file
  lang::Span at;            ///< the definition (for notes)
};

/// A scope of parameters, inside an outer one.
class ParamScope {
public:
  /// A scope inside `parent` (nullptr: the netlist's own).
  explicit ParamScope(const ParamScope* parent) : parent_(parent) {}
  /// Defines a parameter by an expression (evaluated in this scope when first used); throws
  /// ImportError when this scope defines it already.
  void define(const std::string& name, ParamDef def);
  /// Whether this scope itself (not an outer one) defines or sets `name`.
  bool lookup_here(const std::string& name) const {
    return values_.count(name) > 0 || defs_.count(name) > 0;
  }
  /// Sets a parameter to a value (an instance's parameter, evaluated where the instance stands).
  void set(const std::string& name, double value) { values_[name] = value; }
  /// The value of a parameter (lower case) here or in an outer scope; nothing when none has it.
  std::optional<double> lookup(const std::string& name) const;
  /// The value of a token: an expression, a number with its suffix, or a parameter's name; throws
  /// ImportError otherwise. `femto` is set when the number's suffix is a lone f (femto).
  double value(const Token& t, bool* femto = nullptr) const;
  /// The value of a definition's expression in this scope; throws ImportError.
  double evaluate(const ParamDef& def) const;
  /// The expression spanning tokens [first, last) of a card (`.param c = a * 2` without braces).
  static ParamDef definition(const lang::SourceManager& sources, const std::vector<Token>& tokens,
                             std::size_t first, std::size_t last);

private:
  const ParamScope* parent_;
  std::map<std::string, ParamDef> defs_;
  mutable std::map<std::string, double> values_;
  mutable std::set<std::string> busy_;
};

/// Reads `NAME = VALUE ...` pairs from tokens[from, end) into `out` (name lower case); a pair's
/// value runs up to the next `NAME =`. Throws ImportError for a malformed list.
void read_assignments(const lang::SourceManager& sources, const std::vector<Token>& tokens,
                      std::size_t from, std::vector<std::pair<std::string, ParamDef>>& out);

} // namespace thermnet::importer::spice
