#pragma once
/// Elaboration: turns a Model's declarations, for one case and one set of param values, into a
/// NetworkSpec, reporting every problem through a callback (lint collects, simulate throws).

#include "lang/csv.hpp"
#include "lang/evaluator.hpp"
#include "lang/model.hpp"

#include <functional>
#include <optional>
#include <set>
#include <unordered_map>

namespace thermnet::lang {

/// Receives each problem found; may throw to stop at the first error.
using Reporter = std::function<void(Diagnostic)>;

/// Evaluates and checks one instantiation of a model.
class Elaborator {
public:
  /// Elaborates `model` for case `c` (nullptr: the base model) with param overrides.
  Elaborator(const Model& model, Reporter report, const CaseDecl* c, const ParamValues& overrides,
             bool check_data);
  /// Builds the network; problems go to the reporter (the result is partial after an error).
  NetworkSpec run();
  /// Names of consts and params looked up during run().
  const std::set<std::string>& used_names() const { return used_; }
  /// The value of a const or param (evaluated on first use); throws EvalError.
  Quantity value_of(const std::string& name, Span use);
  /// The evaluated range of a ranged param, if value_of evaluated it.
  std::optional<std::pair<double, double>> range_of(const std::string& name) const {
    auto it = ranges_.find(name);
    return it == ranges_.end() ? std::nullopt : std::optional(it->second);
  }

private:
  /// Where a value goes: what to call it in messages, and what it must be.
  struct Place {
    /// Forms "key 'k' of conduction 'g1'"; called only when a message needs it.
    std::function<std::string()> describe;
    Dimension dim;                     ///< expected dimension
    bool absolute_temperature = false; ///< bare numbers are degC
    const KeySchema* key = nullptr;    ///< for range checks
    /// The description of the place for messages.
    std::string what() const { return describe(); }
  };

  Evaluator evaluator(FileId f);
  std::optional<double> to_place(const Quantity& q, const Place& p, Span at, Span mark);
  std::optional<double> number(const ast::Expr& e, FileId f, const Place& p, Span at);
  std::optional<Signal> signal(const ast::Value& v, FileId f, const Place& p, Span at);
  bool check_range(double v, const Place& p, Span at, Span mark);
  std::optional<int> resolve_node(const ast::Identifier& id, FileId f, Span at);
  void report(Diagnostic d);

  void elaborate_node(const NodeDecl& d, NodeSpec& out);
  bool fill_keys(const ElementSchema& schema, const std::vector<ast::KeyValue>& keys, FileId f,
                 Span at, const std::function<std::string()>& owner, ElementSpec& out);
  std::optional<ElementSpec> elaborate_element(const ElementDecl& d);
  std::optional<ElementSpec> elaborate_composite(const ElementDecl& d);
  void apply_case(NetworkSpec& net);
  void apply_override(NetworkSpec& net, const ast::CaseAssign& a, FileId f);
  void check_data(const NetworkSpec& net, const std::string& path, Span at, Span mark);
  /// Warns about rows of the case's data file after its duration (read by check_data()).
  void warn_data_beyond_duration(const CaseSettings& s);

  const Model& m_;
  Reporter report_;
  const CaseDecl* case_;
  ParamValues overrides_;
  bool check_data_;
  /// The time column of the case's data file and where the case names it.
  struct DataTimes {
    CsvTable table; ///< the time column only
    Span at;        ///< the data statement
    Span mark;      ///< its path
  };
  std::optional<DataTimes> data_times_; ///< set by check_data()
  std::unordered_map<std::string, const ValueDecl*> value_decls_;
  std::unordered_map<std::string, Quantity> values_;
  std::unordered_map<std::string, std::pair<double, double>> ranges_;
  std::map<std::string, double> pending_params_;
  std::vector<std::string> evaluating_;
  std::set<std::string> used_;
  std::vector<int> element_slot_; // per element declaration: index in the network, or -1
};

} // namespace thermnet::lang
