#pragma once
/// A model instantiated for one case and one set of param values: resolved names, values in SI.

#include "lang/csv.hpp"
#include "lang/requirement.hpp"
#include "lang/schema.hpp"
#include "lang/signal.hpp"
#include "lang/source.hpp"

#include <boost/container/small_vector.hpp>

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace thermnet::lang {

/// A value kept on the heap only when present, copied with its owner (for members most objects
/// leave empty: a null pointer weighs 8 bytes where an empty string or vector weighs 24-32).
template <class T> class Rare {
public:
  /// Empty.
  Rare() = default;
  /// A copy with its own value.
  Rare(const Rare& other) : p_(other.p_ ? std::make_unique<T>(*other.p_) : nullptr) {}
  /// Takes another's value.
  Rare(Rare&&) noexcept = default;
  /// Copies another's value.
  Rare& operator=(const Rare& other) {
    if (this != &other) p_ = other.p_ ? std::make_unique<T>(*other.p_) : nullptr;
    return *this;
  }
  /// Takes another's value.
  Rare& operator=(Rare&&) noexcept = default;
  /// The value, or nullptr if none was made.
  const T* get() const { return p_.get(); }
  /// The value to modify, or nullptr if none was made.
  T* get() { return p_.get(); }
  /// The value, made (default) on first use.
  T& make() {
    if (!p_) p_ = std::make_unique<T>();
    return *p_;
  }

private:
  std::unique_ptr<T> p_;
};

/// A node (unknown temperature) or a boundary (prescribed temperature).
struct NodeSpec {
  std::string name;         ///< node name
  double C = 0.0;           ///< heat capacity, J/K (0: arithmetic node)
  std::optional<double> T0; ///< initial temperature, K (nodes; else the case's initial)
  Signal T;                 ///< prescribed temperature, K (boundaries)
  Span where;               ///< declaring statement
  bool boundary = false;    ///< true for a boundary

  /// Description (empty when none was written).
  const std::string& doc() const;
  /// Sets the description (an empty one takes no memory).
  void set_doc(std::string_view text);

private:
  Rare<std::string> doc_;
};

/// The values of an element's keys by name, in key order, with the interface of a std::map: a
/// sorted flat list whose key names are views of the element schema's key names (stable for the
/// life of the process), and whose first key is kept inline (most elements have one).
class KeySignals {
public:
  /// A key name (a view of the schema's) and its value.
  using value_type = std::pair<std::string_view, Signal>;

private:
  using Items = boost::container::small_vector<value_type, 1>;

public:
  /// Iterators over the keys in order.
  using iterator = Items::iterator;
  /// Read-only iterators over the keys in order.
  using const_iterator = Items::const_iterator;

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
  /// The value of a schema key, inserted (a constant 0) if absent; the list keeps a view of
  /// key.name, so the schema must outlive it (a registered kind's schema lives with the process).
  Signal& operator[](const KeySchema& key);
  /// Inserts a schema key's value unless the key has one (see operator[]); the entry and whether
  /// it was inserted.
  std::pair<iterator, bool> emplace(const KeySchema& key, Signal value);

private:
  iterator lower_bound(std::string_view key);
  Items items_;
};

/// How a series/parallel block combines its parts.
enum class Composite : std::uint8_t { none, series, parallel };

/// One element between nodes, with every key evaluated (defaults filled in).
///
/// Laid out for networks of a million elements: the kind is its schema's, the terminals are
/// inline, and what few elements have (node-valued keys, the parts of a composite) lives behind
/// one pointer.
class ElementSpec {
public:
  const ElementSchema* schema = nullptr; ///< its kind's schema (nullptr for a composite)
  std::string name;                      ///< element name (empty for composite parts)
  KeySignals values;                     ///< key -> value in SI (numbers as constant signals)
  Span where;                            ///< declaring statement

  /// Kind name: the schema's, "series"/"parallel" for a composite ("" when neither is set).
  std::string_view kind() const;
  /// Terminal node indices (one or two, as the kind's schema says; a sensor of a mean: several).
  std::span<const int> nodes() const;
  /// Sets the terminal node indices (one or two, several for a sensor whose schema is set; throws
  /// std::invalid_argument otherwise).
  void set_nodes(std::span<const int> nodes);
  /// Composite mode (none for an element of a kind).
  Composite composite() const { return composite_; }
  /// Makes the element a series or parallel block (kind() then names the mode).
  void set_composite(Composite mode) { composite_ = mode; }
  /// Inner elements of a composite (empty otherwise).
  std::span<const ElementSpec> parts() const;
  /// Inner elements of a composite, to be modified or added to.
  std::vector<ElementSpec>& edit_parts();

  /// A constant key value (throws std::out_of_range if absent).
  double number(std::string_view key) const { return values.at(key).constant; }
  /// True if a key has a value.
  bool has(std::string_view key) const { return values.count(key) != 0; }
  /// Sets the value of a key of the schema; throws std::invalid_argument when the element has no
  /// schema or its schema no such key.
  void set(std::string_view key, Signal value);
  /// The node index of a node-valued key, or nullopt if it was not given.
  std::optional<int> node_key(std::string_view key) const;
  /// Records a node-valued key of the schema (e.g. sense) and its node index.
  void add_node_key(const KeySchema& key, int node);
  /// The constant values of all keys, for schema functions.
  KeyValues key_values() const;

private:
  /// What few elements have.
  struct Extras {
    /// Node-valued keys (names viewing the schema's) and their node indices, in the order given.
    std::vector<std::pair<std::string_view, int>> node_keys;
    std::vector<ElementSpec> parts; ///< inner elements of a composite
    std::vector<int> nodes;         ///< terminals of a sensor of more than two nodes
  };
  std::array<int, 2> nodes_{-1, -1};      // terminal node indices
  std::uint8_t terminals_ = 0;            // how many of nodes_ are used
  Composite composite_ = Composite::none; // composite mode
  Rare<Extras> extras_;                   // node-valued keys and parts, when any
};

/// One measured series of a case's data file as a column map gives it: what it is compared with,
/// and the columns (their weighted mean) it is read from.
struct DataSeries {
  std::string target;               ///< node, boundary or sensor (full name)
  std::vector<std::string> columns; ///< the file's columns
  std::vector<double> weights;      ///< their weights, summing to 1
  double scale = 1.0;               ///< a mean m is scale * m + offset degC
  double offset = 0.0;              ///< (from the unit written after the columns)
  Span where;                       ///< the map's entry
};

/// Settings of the case the network was instantiated for.
struct CaseSettings {
  std::string name = "default";   ///< case name
  std::optional<double> duration; ///< simulated time, s
  std::optional<double> initial;  ///< initial temperature of nodes without T0, K
  bool initial_steady = false;    ///< `initial = steady`: start from the steady state at t = 0
  /// `initial = data`: measured nodes start at their first measured values (their T0), the
  /// others at the steady state around them at t = 0.
  bool initial_data = false;
  std::optional<double> output;        ///< output interval, s
  std::vector<double> output_times;    ///< listed output times, s (`output = 0, 100, 250`)
  std::string data_path;               ///< measured data file (resolved path), if any
  double data_scale = 1.0;             ///< a data value v is data_scale * v + data_offset degC
  double data_offset = 0.0;            ///< (from the unit of `data "file.csv" [K]`)
  CsvLayout data_layout;               ///< the data file's time column and separator
  double data_epoch = 0.0;             ///< absolute time of the case's start (absolute layouts), s
  bool data_mapped = false;            ///< a column map names the series (other columns unused)
  std::vector<DataSeries> data_series; ///< the column map
  Span data_where;                     ///< the data statement
  Span where;                          ///< the case statement (empty for the implicit default)
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
