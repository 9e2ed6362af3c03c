#pragma once
/// The network an importer reads from another tool's file, before it is written as thermnet text:
/// nodes, boundaries, links and heaters under thermnet names, each value as the thermnet
/// expression to write (with its SI value), and where each came from.

#include "lang/source.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace thermnet::importer {

/// A name as thermnet writes it: an identifier with an optional whole-number index (`MAIN[63]`).
struct Name {
  std::string base;                  ///< the identifier
  std::optional<std::int64_t> index; ///< the index, if any
  /// `base`, or `base[index]`.
  std::string text() const;
  /// Equal base and index.
  friend bool operator==(const Name&, const Name&) = default;
};

/// A value: the thermnet expression written for it and its value in SI units (kelvin for a
/// temperature).
struct Value {
  std::string text; ///< thermnet expression, e.g. `2.5 * C_unit`, `20` or `293 [K]`
  double si = 0;    ///< its value in SI units
};

/// A value that may change over time: a constant, or the points of a piecewise-linear signal.
struct Signal {
  Value constant;                              ///< the value while `points` is empty
  std::vector<std::pair<Value, Value>> points; ///< (time, value) of a pwl, times increasing
};

/// A node with a heat capacity (C = 0: an arithmetic node).
struct Node {
  Name name;               ///< thermnet name
  Value C;                 ///< capacity [J/K]
  std::optional<Value> T0; ///< initial temperature, if the source gives one
  std::string what;        ///< how the source names it, for the comment ("" when the name says it)
  lang::Span origin;       ///< the line it came from
};

/// A node held at a prescribed temperature.
struct Boundary {
  Name name;         ///< thermnet name
  Signal T;          ///< temperature
  std::string what;  ///< how the source names it ("" when the name says it)
  lang::Span origin; ///< the line it came from
};

/// The element kind a link is written as.
enum class LinkKind { conductance, resistor, radiation };

/// A two-terminal element between nodes or boundaries.
struct Link {
  LinkKind kind = LinkKind::conductance; ///< conductance (G), resistor (R) or radiation (GR)
  Name name;                             ///< element name
  Name a;                                ///< first terminal
  Name b;                                ///< second terminal
  Value value;                           ///< G [W/K], R [K/W] or GR [m^2]
  std::string what;                      ///< how the source names it ("" when the name says it)
  lang::Span origin;                     ///< the line it came from
};

/// A heat input into a node.
struct Heater {
  Name name;                       ///< element name
  Name node;                       ///< the heated node
  Signal P;                        ///< power [W]
  std::string what;                ///< how the source names it ("" when the name says it)
  std::vector<lang::Span> origins; ///< the lines it adds up (a source and a VARIABLES 0 load)
};

/// A const the written model declares (a unit conversion, the deck's SIGMA).
struct Const {
  std::string name;    ///< identifier
  std::string expr;    ///< thermnet expression
  std::string comment; ///< what it is
};

/// The case a source's analysis statement gives (SINDA's TIMEND, SPICE's .tran).
struct CaseSpec {
  std::string name;            ///< case name
  Value duration;              ///< simulated time [s]
  std::optional<Value> output; ///< output interval [s]
  std::string initial;         ///< `initial = ...` setting ("" for none, e.g. "steady")
  lang::Span origin;           ///< the statement it came from
};

/// Everything read, ready to be written.
struct Network {
  std::string format;                ///< "SINDA/FLUINT" or "SPICE"
  std::string model;                 ///< model name (an identifier)
  std::vector<std::string> heading;  ///< comment lines for the top (title, units, name scheme)
  std::vector<Const> consts;         ///< consts to declare
  std::vector<Boundary> boundaries;  ///< boundaries, in writing order
  std::vector<Node> nodes;           ///< nodes, in writing order
  std::vector<Link> links;           ///< links, in writing order
  std::vector<Heater> heaters;       ///< heaters, in writing order
  std::optional<CaseSpec> case_spec; ///< the case, if the source gives an analysis
};

/// Most output rows an imported case asks for: a finer interval (SPICE's TSTEP of 1 us over 10 s)
/// would make every simulation write millions of rows; the case then takes duration / this.
inline constexpr double max_output_rows = 100000;

/// A model name made of a file's name: its stem with every character that cannot stand in a name
/// replaced by `_` (prefixed when it would start with a digit or be empty).
std::string model_name(const std::string& path, const std::string& prefix);

/// A number written so that reading it back gives the same double (shortest round-trip form).
std::string number_text(double v);

} // namespace thermnet::importer
