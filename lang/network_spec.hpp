#pragma once
/// A model instantiated for one case and one set of param values: resolved names, values in SI.

#include "lang/requirement.hpp"
#include "lang/schema.hpp"
#include "lang/signal.hpp"
#include "lang/source.hpp"

#include <map>
#include <optional>
#include <string>
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

/// How a series/parallel block combines its parts.
enum class Composite { none, series, parallel };

/// One element between nodes, with every key evaluated (defaults filled in).
struct ElementSpec {
  const ElementSchema* schema = nullptr; ///< its kind's schema (nullptr for a composite)
  std::string kind;                      ///< kind name ("series"/"parallel" for composites)
  std::string name;                      ///< element name (empty for composite parts)
  std::vector<int> nodes;                ///< terminal node indices
  std::map<std::string, Signal> values;  ///< key -> value in SI (numbers as constant signals)
  std::map<std::string, int> node_keys;  ///< node-valued keys (e.g. sense) -> node index
  Composite composite = Composite::none; ///< composite mode
  std::vector<ElementSpec> parts;        ///< inner elements of a composite
  Span where;                            ///< declaring statement

  /// A constant key value (throws std::out_of_range if absent).
  double number(const std::string& key) const { return values.at(key).constant; }
  /// True if a key has a value.
  bool has(const std::string& key) const { return values.count(key) != 0; }
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
