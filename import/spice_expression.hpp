#pragma once
/// SPICE parameter expressions (`{r1 * 2}`, `.param c = tau / r`): numbers with scale suffixes,
/// parameter names, + - * / ^ (and **), parentheses, and the functions sqrt exp ln log (natural,
/// as in ngspice) log10 abs min max pow pwr sin cos tan atan sinh cosh tanh floor ceil int.

#include "lang/source.hpp"

#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace thermnet::importer::spice {

/// The value of a parameter name (lower case), or nothing when no parameter has that name; may
/// throw ImportError (a cycle, an error in the parameter's own expression).
using ParamLookup = std::function<std::optional<double>(const std::string& name)>;

/// Evaluates `text` (the expression, without its braces) that starts at byte `offset` of file
/// `file`; throws ImportError at the offending character (code `bad-expression`), for a name no
/// parameter has (`unknown-param`), and for a result that is not finite.
double evaluate(std::string_view text, lang::FileId file, std::uint32_t offset,
                const ParamLookup& lookup);

/// The thermnet text of a parameter's name (a name of the submodel, or a number), or nothing when
/// it has none.
using NameText = std::function<std::optional<std::string>(const std::string& name)>;

/// `text` (an expression that evaluates) as a thermnet expression with the same value, its names
/// written by `name_text`; nothing when a name or function has no thermnet counterpart.
std::optional<std::string> translate(std::string_view text, const NameText& name_text);

} // namespace thermnet::importer::spice
