#pragma once
/// Parameter schemas of element kinds: one description drives parsing checks, lint, docs and
/// completion.

#include "lang/units.hpp"

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace thermnet::lang {

/// What a key accepts.
enum class KeyType {
  number, ///< a constant expression
  signal, ///< a constant expression or a time signal (step, pwl, table)
  node    ///< the name of a node or boundary
};

/// One key of an element kind: name, unit dimension, required/default, valid range, one-line doc.
struct KeySchema {
  std::string name;                    ///< key as written in models
  Dimension dim;                       ///< expected unit dimension
  KeyType type = KeyType::number;      ///< number, signal or node name
  bool required = false;               ///< must be given (unless covered by an alternative group)
  std::optional<double> default_value; ///< SI default when not given
  std::optional<double> min;           ///< smallest valid SI value
  std::optional<double> max;           ///< largest valid SI value
  bool min_exclusive = false;          ///< min itself is invalid
  bool max_exclusive = false;          ///< max itself is invalid
  bool absolute_temperature = false;   ///< bare numbers are degC (converted to K)
  bool temperature_difference = false; ///< a difference: 0.4 [degC] or 0.4 [degF] * 9/5 is 0.4 K
  bool lag = false; ///< a time constant integrated as a state (0: none; see unresolved_lag())
  std::string doc;  ///< one-line documentation with the unit
  std::string with; ///< an optional part of the alternative group holding this key (F: "A")

  /// "in (0, 1]", "> 0", ... for messages; empty when unbounded.
  std::string range_text() const;
  /// True when an SI value lies in the valid range.
  bool accepts(double v) const;
};

/// True when a lag (a KeySchema::lag value, s) is positive but far shorter than a run of
/// `duration` s can resolve (below 1e-7 of it, or so short that its reciprocal overflows): it is
/// then taken as no lag.
bool unresolved_lag(double lag, std::optional<double> duration);

/// Values of an element's keys in SI, by key name (absent keys carry their defaults).
using KeyValues = std::map<std::string, double, std::less<>>;

/// A problem found by a schema's cross-key check: the key it concerns and a message.
struct KeyProblem {
  std::string key;     ///< key to point at
  std::string message; ///< complete message, e.g. "r_out must be larger than r_in"
};

/// The schema of one element kind.
struct ElementSchema {
  std::string kind;            ///< kind name, e.g. "conduction"
  int terminals = 2;           ///< number of terminal nodes (1 or 2)
  std::string doc;             ///< one-line documentation
  std::vector<KeySchema> keys; ///< its keys
  /// Groups of keys of which exactly one must be given in full (radiation: {GR} or {A, eps1,
  /// eps2}).
  std::vector<std::vector<std::string>> alternatives;
  /// Cross-key checks on the evaluated values (e.g. r_out > r_in); may be empty.
  std::function<std::vector<KeyProblem>(const KeyValues&)> check;
  /// For linear elements: the conductance in W/K from the key values (used by series blocks).
  std::function<double(const KeyValues&)> conductance;
  /// True for heat sources (not allowed on boundaries).
  bool is_source = false;
  /// True for a sensor: it reads its terminal (or the mean of several, `mean(a, b)`), carries no
  /// heat, and a measured series of its node is compared with its reading.
  bool observes = false;

  /// The key schema of a name, or nullptr.
  const KeySchema* key(std::string_view name) const;
  /// Names of all keys, for suggestions.
  std::vector<std::string> key_names() const;
};

/// Looks up element schemas by kind; implemented by the kernel's element registry.
class ElementCatalog {
public:
  virtual ~ElementCatalog() = default;
  /// The schema of a kind, or nullptr if unknown.
  virtual const ElementSchema* find(std::string_view kind) const = 0;
  /// All known kind names, sorted.
  virtual std::vector<std::string> kinds() const = 0;
};

} // namespace thermnet::lang
