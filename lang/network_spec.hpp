#pragma once
/// A model instantiated for one case and one set of param values: resolved names, values in SI.

#include "lang/requirement.hpp"
#include "lang/schema.hpp"
#include "lang/signal.hpp"
#include "lang/source.hpp"

#include <boost/container/small_vector.hpp>

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace thermnet::lang {

/// A node (unknown temperature) or a boundary (prescribed temperature).
struct NodeSpec {
  std::string name;         ///< node name
  bool boundary = false;    ///< true for a boundary
  double C = 0.0;           ///< heat capacity, J/K (0: arithmetic node)
  std::optional<double> T0; ///< initial temperature, K (nodes; else the case's initial)
  Signal T;                 ///< prescribed temperature, K (boundaries)
  std::string doc;          ///< description
  Span where;               ///< declaring statement
};

/// The values of an element's keys by name, in key order, with the interface of the std::map it
/// replaces: a sorted flat list (an element has a handful of keys, and a list costs one
/// allocation where a map costs one per key).
class KeySignals {
public:
  /// A key and its value.
  using value_type = std::pair<std::string, Signal>;
  /// Iterators over the keys in order.
  using iterator = std::vector<value_type>::iterator;
  /// Read-only iterators over the keys in order.
  using const_iterator = std::vector<value_type>::const_iterator;

  /// First key.
  iterator begin() { return items_.begin(); }
  /// Past the last key.
  iterator end() { return items_.end(); }
  /// First key.
  const_iterator begin() const { return items_.begin(); }
  /// Past the last key.
  const_iterator end() const { return items_.end(); }
  /// Number of keys.
  std::size_t size() const { return items_.size(); }
  /// True without keys.
  bool empty() const { return items_.empty(); }
  /// Room for n keys without reallocating.
  void reserve(std::size_t n) { items_.reserve(n); }
  /// The key's entry, or end().
  iterator find(std::string_view key);
  /// The key's entry, or end().
  const_iterator find(std::string_view key) const;
  /// 1 if the key has a value, else 0.
  std::size_t count(std::string_view key) const { return find(key) == end() ? 0 : 1; }
  /// The value of a key; throws std::out_of_range if absent.
  Signal& at(std::string_view key);
  /// The value of a key; throws std::out_of_range if absent.
  const Signal& at(std::string_view key) const;
  /// The value of a key, inserted (a constant 0) if absent.
  Signal& operator[](std::string_view key);
  /// Inserts a key's value unless the key has one; the entry and whether it was inserted.
  std::pair<iterator, bool> emplace(std::string_view key, Signal value);

private:
  iterator lower_bound(std::string_view key);
  std::vector<value_type> items_;
};

/// How a series/parallel block combines its parts.
enum class Composite { none, series, parallel };

/// One element between nodes, with every key evaluated (defaults filled in).
struct ElementSpec {
  const ElementSchema* schema = nullptr; ///< its kind's schema (nullptr for a composite)
  std::string kind;                      ///< kind name ("series"/"parallel" for composites)
  std::string name;                      ///< element name (empty for composite parts)
  /// Terminal node indices, inline (an element has one or two: no allocation per element).
  boost::container::small_vector<int, 2> nodes;
  KeySignals values; ///< key -> value in SI (numbers as constant signals)
  /// Node-valued keys (e.g. sense) and their node indices, in the order given (a flat list: few
  /// elements have one, and an empty map weighed 48 bytes in every element).
  std::vector<std::pair<std::string, int>> node_keys;
  Composite composite = Composite::none; ///< composite mode
  std::vector<ElementSpec> parts;        ///< inner elements of a composite
  Span where;                            ///< declaring statement

  /// A constant key value (throws std::out_of_range if absent).
  double number(const std::string& key) const { return values.at(key).constant; }
  /// True if a key has a value.
  bool has(const std::string& key) const { return values.count(key) != 0; }
  /// The node index of a node-valued key, or nullopt if it was not given.
  std::optional<int> node_key(std::string_view key) const;
  /// The constant values of all keys, for schema functions.
  KeyValues key_values() const;
};

/// Settings of the case the network was instantiated for.
struct CaseSettings {
  std::string name = "default";     ///< case name
  std::optional<double> duration;   ///< simulated time, s
  std::optional<double> initial;    ///< initial temperature of nodes without T0, K
  bool initial_steady = false;      ///< `initial = steady`: start from the steady state at t = 0
  std::optional<double> output;     ///< output interval, s
  std::vector<double> output_times; ///< listed output times, s (`output = 0, 100, 250`)
  std::string data_path;            ///< measured data file (resolved path), if any
  double data_scale = 1.0;          ///< a data value v is data_scale * v + data_offset degC
  double data_offset = 0.0;         ///< (from the unit of `data "file.csv" [K]`)
  Span where;                       ///< the case statement (empty for the implicit default)
};

/// A network ready for the kernel: nodes, boundaries and elements in SI.
struct NetworkSpec {
  std::string model;                         ///< model name
  std::vector<NodeSpec> nodes;               ///< nodes and boundaries, in declaration order
  std::vector<ElementSpec> elements;         ///< elements in declaration order
  CaseSettings settings;                     ///< the case
  std::vector<RequirementSpec> requirements; ///< the `require` statements that apply to the case

  /// Index of a node or boundary by name, or -1.
  int node_index(const std::string& name) const;
  /// Default initial temperature: the case's, else 20 degC.
  double default_initial() const { return settings.initial.value_or(293.15); }
};

} // namespace thermnet::lang
