#pragma once
/// The network an importer reads from another tool's file, before it is written as thermnet text:
/// nodes, boundaries, links and heaters under thermnet names, each value as the thermnet
/// expression to write (with its SI value), and where each came from.

#include "import/report.hpp"
#include "lang/source.hpp"

#include <cstdint>
#include <functional>
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
  Value() = default;
  /// A value written as `text`, `si` in SI units, and in its subcircuit's params as `scoped`.
  Value(std::string text_, double si_, std::string scoped_ = {})
      : text(std::move(text_)), si(si_), scoped(std::move(scoped_)) {}
  std::string text;   ///< thermnet expression, e.g. `2.5 * C_unit`, `20` or `293 [K]`
  double si = 0;      ///< its value in SI units
  std::string scoped; ///< SPICE: the value in its subcircuit's params ("": only `text` applies)
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
  std::size_t scope = 0;   ///< SPICE: the subcircuit instance it stands in (0: the top level)
};

/// A node held at a prescribed temperature.
struct Boundary {
  Name name;             ///< thermnet name
  Signal T;              ///< temperature
  std::string what;      ///< how the source names it ("" when the name says it)
  lang::Span origin;     ///< the line it came from
  std::size_t scope = 0; ///< SPICE: the subcircuit instance it stands in (0: the top level)
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
  std::size_t scope = 0; ///< SPICE: the subcircuit instance it stands in (0: the top level)
};

/// A heat input into a node.
struct Heater {
  Name name;                       ///< element name
  Name node;                       ///< the heated node
  Signal P;                        ///< power [W]
  std::string what;                ///< how the source names it ("" when the name says it)
  std::vector<lang::Span> origins; ///< the lines it adds up (a source and a VARIABLES 0 load)
  std::size_t scope = 0;           ///< SPICE: the subcircuit instance it stands in (0: top level)
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

/// An instance of a submodel: `SUBMODEL NAME NODE ... key = value ...`.
struct InstanceStmt {
  std::string submodel;                                  ///< the submodel
  std::string name;                                      ///< the instance's name
  std::vector<std::string> nodes;                        ///< the nodes its terminals connect to
  std::vector<std::pair<std::string, std::string>> keys; ///< params it sets (name, expression)
  std::string what;                                      ///< how the source names it
  lang::Span origin;                                     ///< the line it came from
};

/// A param of a submodel.
struct SubmodelParam {
  std::string name;                    ///< identifier
  std::optional<std::string> default_; ///< its default (none: every instance gives it)
  lang::Span origin;                   ///< where the source defines it
};

/// A submodel: a part the source defines once and uses several times (a SPICE subcircuit).
struct Submodel {
  std::string name;                    ///< submodel name
  std::vector<std::string> terminals;  ///< its terminals, in order
  std::vector<SubmodelParam> params;   ///< its params
  std::vector<Const> consts;           ///< its consts
  std::vector<Boundary> boundaries;    ///< its boundaries
  std::vector<Node> nodes;             ///< its nodes
  std::vector<Link> links;             ///< its links
  std::vector<Heater> heaters;         ///< its heaters
  std::vector<InstanceStmt> instances; ///< the instances inside it
  std::string what;                    ///< how the source names it
  lang::Span origin;                   ///< where the source defines it
};

/// How many of each a model holds with every instance expanded.
struct Counts {
  std::size_t nodes = 0, boundaries = 0, links = 0, heaters = 0; ///< the numbers
};

/// Everything read, ready to be written.
struct Network {
  std::string format;                  ///< "SINDA/FLUINT" or "SPICE"
  std::string model;                   ///< model name (an identifier)
  std::vector<std::string> heading;    ///< comment lines for the top (title, units, name scheme)
  std::vector<Const> consts;           ///< consts to declare
  std::vector<Boundary> boundaries;    ///< boundaries, in writing order
  std::vector<Node> nodes;             ///< nodes, in writing order
  std::vector<Link> links;             ///< links, in writing order
  std::vector<Heater> heaters;         ///< heaters, in writing order
  std::optional<CaseSpec> case_spec;   ///< the case, if the source gives an analysis
  std::vector<Submodel> submodels;     ///< submodels, each before its first use
  std::vector<InstanceStmt> instances; ///< top-level instances of submodels
  std::optional<Counts> expanded;      ///< with submodels: the counts with instances expanded
};

/// Notes every node that no chain of links ties to a boundary (a floating part of the network,
/// whose steady state is undetermined and of which lint warns); `shown` names a node in the note.
void note_floating(const Network& net, Report& report,
                   const std::function<std::string(const Name&)>& shown);

/// Most output rows an imported case asks for: a finer interval (SPICE's TSTEP of 1 us over 10 s)
/// would make every simulation write millions of rows; the case then takes duration / this.
inline constexpr double max_output_rows = 100000;

/// A model name made of a file's name: its stem with every character that cannot stand in a name
/// replaced by `_` (prefixed when it would start with a digit or be empty).
std::string model_name(const std::string& path, const std::string& prefix);

/// A number written so that reading it back gives the same double (shortest round-trip form).
std::string number_text(double v);

} // namespace thermnet::importer
