#pragma once
/// Elaboration: evaluates a Model's declarations, for one case and one set of param values, into a
/// NetworkSpec, reporting every problem through a callback (lint collects, simulate throws).
///
/// Declarations stand in scopes (loop iterations, submodel instances); a name in an expression is
/// looked up in the loop variables around it, then in its instance's params and consts, then in
/// the model's consts and params. The model loader uses an elaborator in structural mode, where a
/// param may not be used (loop ranges, indices and instance sizes cannot change per case).

#include "lang/csv.hpp"
#include "lang/evaluator.hpp"
#include "lang/model.hpp"

#include <functional>
#include <optional>
#include <set>
#include <unordered_map>

namespace thermnet::lang {

/// Longest chain of keys read through one another (`a.P` reads `b.P`, which reads `c.P` ...) that
/// is resolved; each link is a level of recursion.
inline constexpr std::size_t max_reference_depth = 100;

/// Receives each problem found; may throw to stop at the first error.
using Reporter = std::function<void(Diagnostic)>;

/// The name of a node's start temperature calibrated in one case (`w.T0 = 20 range 15 .. 30` in
/// case `lid`): `w.T0@lid`.
std::string case_param_name(std::string_view node, std::string_view case_name);

/// The schema of node statements (keys C, T0), checked like an element's.
const ElementSchema& node_schema();
/// The schema of boundary statements (key T).
const ElementSchema& boundary_schema();

/// The params a value read, directly or through the consts and instance values it read.
using ParamReads = std::vector<const ValueDecl*>;

/// One elaboration of a case kept to elaborate it again at nearby param values
/// (Elaborator::run_near()): the network before the case's settings and what each node and
/// element declaration read.
struct ElaborationRecord {
  std::string case_name;                 ///< the case elaborated
  ParamValues params;                    ///< the param overrides it was elaborated with
  NetworkSpec declared;                  ///< its nodes and elements before the case's settings
  std::vector<ParamReads> node_reads;    ///< per node: the params its values read
  std::vector<ParamReads> element_reads; ///< per element declaration: the params its values read
  std::vector<int> element_slot;         ///< per element declaration: index in declared.elements
};

/// Evaluates and checks one instantiation of a model.
class Elaborator {
public:
  /// Elaborates `model` for case `c` (nullptr: the base model) with param overrides and the
  /// values set from outside the model, which take precedence over the case's: `external`, or
  /// when it is nullptr the model's own (Model::overrides()).
  Elaborator(const Model& model, Reporter report, const CaseDecl* c, const ParamValues& overrides,
             bool check_data, const Overrides* external = nullptr);
  /// An elaborator for the structure of a model being loaded: params are refused.
  static Elaborator structural(const Model& model, Reporter report);

  /// Builds the network; problems go to the reporter (the result is partial after an error).
  NetworkSpec run();
  /// run() from a record of the same case (none: the same as run()) at param overrides that differ
  /// from the record's in the params `moved` (declarations of the model's params) only: the nodes
  /// and elements that read none of them are copied from it, the others elaborated again, the
  /// case's settings applied afresh. With `record`, keeps there what a later run_near() needs
  /// (nothing when a value reads another key: such values are resolved with the case's settings).
  NetworkSpec run_near(const ElaborationRecord* from, const ParamReads& moved,
                       std::optional<ElaborationRecord>* record);
  /// The declaration of a top-level param or const, or nullptr.
  const ValueDecl* value_decl(std::string_view name) const {
    auto it = value_decls_.find(name);
    return it == value_decls_.end() ? nullptr : it->second;
  }
  /// Applies the case to `net`, the network `base` built without a case (run() on the base
  /// model): the same as run() when the case sets no param, without elaborating again.
  NetworkSpec run_on(NetworkSpec net, const Elaborator& base);
  /// True when a case block sets a param (its nodes and elements may then differ from the base
  /// model's).
  static bool sets_params(const CaseDecl& c);
  /// True when some value reads another key (`P = film.P`): each case's network is then
  /// elaborated on its own rather than applied to the base model's.
  bool reads_keys() const { return !references_.empty(); }
  /// Names of consts and params looked up during run().
  const std::set<std::string, std::less<>>& used_names() const { return used_; }
  /// The value of a top-level const or param (evaluated on first use); throws EvalError.
  Quantity value_of(std::string_view name, Span use);
  /// The evaluated range of a ranged param, if value_of evaluated it.
  std::optional<std::pair<double, double>> range_of(std::string_view name) const {
    auto it = ranges_.find(name);
    return it == ranges_.end() ? std::nullopt : std::optional(it->second);
  }

  /// Evaluates an expression written in `file` inside `scope`; throws EvalError.
  Quantity evaluate(const ast::Expr& e, FileId file, const Scope* scope);
  /// A whole number from an expression (loop bounds, indices); throws EvalError.
  long whole_number(const ast::Expr& e, FileId file, const Scope* scope, const char* what);
  /// The full name a reference denotes inside `scope` (indices evaluated, the instance's prefix
  /// not applied): `p[3]`, `w.x`; throws EvalError.
  std::string reference_text(const ast::Ref& r, FileId file, const Scope* scope);
  /// Sets `net`'s requirements to the model's `require` statements that apply to the case (groups
  /// resolved, limits in SI); problems go to the reporter (lang/requirements.cpp).
  void add_requirements(NetworkSpec& net);
  /// The node a reference denotes inside `scope`, or -1; reports nothing.
  int find_node(const ast::Ref& r, FileId file, const Scope* scope);
  /// The node a reference denotes inside `scope`, or nullopt (reported unless it names a
  /// declaration with a syntax error).
  std::optional<int> resolve_node(const ast::Ref& r, FileId file, const Scope* scope, Span at);

private:
  /// Where a value goes: what to call it in messages, and what it must be.
  struct Place {
    /// Forms "key 'k' of conduction 'g1'"; called only when a message needs it.
    std::function<std::string()> describe;
    Dimension dim;                     ///< expected dimension
    bool absolute_temperature = false; ///< bare numbers are degC
    const KeySchema* key = nullptr;    ///< for range checks
    bool time_allowed = false;         ///< `time` may be used (a signal's place)
    /// The description of the place for messages.
    std::string what() const { return describe(); }
  };

  Evaluator evaluator(FileId f, const Scope* scope);
  Quantity lookup(const ast::Identifier& id, FileId f, const Scope* scope);
  Quantity instance_value(const Scope& instance, int index, Span use);
  void evaluate_reads_first(const ValueDecl& decl);
  std::optional<double> to_place(const Quantity& q, const Place& p, Span at, Span mark);
  std::optional<double> number(const ast::Expr& e, FileId f, const Place& p, Span at);
  // Values that change over time (lang/signal_elaboration.cpp).
  /// The case's data file as tables of it read it.
  struct CaseDataFile {
    std::string path; ///< resolved path
    CsvLayout layout; ///< its layout (the data statement's options)
    double epoch = 0; ///< absolute time of the case's start (absolute layouts), s
    Span at;          ///< the data statement
    Span mark;        ///< its path
  };
  /// A table's column as a signal, in SI of the unit written after it (none: bare).
  struct TableValues {
    Signal signal;                ///< step (held) or pwl corners
    std::optional<Dimension> dim; ///< the unit's dimension
  };
  std::optional<Signal> signal(const ast::Value& v, FileId f, const Place& p, Span at,
                               std::string_view owner = {});
  /// A value that reads another key (`P = 0.3 * sun.P`), elaborated once every key is final.
  struct KeyReference {
    std::string owner;       ///< node, boundary or element whose key it is
    std::string kind;        ///< what the owner is ("heater", "boundary"), for messages
    const KeySchema* key;    ///< the key it is the value of
    const ast::Value* value; ///< as written
    FileId file;             ///< where
    const Scope* scope;      ///< its loop iteration or instance
    Span at;                 ///< its statement
    bool resolving = false;  ///< being elaborated (a reference back to it is a cycle)
    bool done = false;       ///< elaborated
  };
  void defer(const ast::Value& v, FileId f, const Place& p, Span at, std::string_view owner);
  void resolve_references(NetworkSpec& net);
  void supersede(std::string_view owner, std::string_view key);
  void resolve(KeyReference& r);
  Quantity referenced_key(const ast::Ref& ref, FileId f, const Scope* scope, Span mark,
                          Signal& out);
  std::optional<Signal> whole_signal(const ast::SignalExpr& se, FileId f, const Place& p, Span at);
  std::optional<Signal> expression_signal(const ast::Expr& e, FileId f, const Place& p, Span at);
  Quantity embedded_signal(ast::Index node, FileId f, const Scope* scope);
  std::optional<CsvLayout> layout_of(const ast::FileOptions& o, FileId f, Span at, bool table);
  const CaseDataFile* case_data_file();
  std::optional<TableValues> table_values(const ast::TableSignal& ts, FileId f, Span at);
  /// Reports a failed evaluation at the statement `at` (unless it was reported already).
  void report_at(const EvalError& err, Span at);
  bool check_range(double v, const Place& p, Span at, Span mark);
  void report(Diagnostic d);
  /// Adds to d a "did you mean" note naming the one of names() nearest `word`; false when none
  /// is near. A repetition report() will drop is not searched (true: a loop of 20,000
  /// iterations would otherwise search every name 20,000 times).
  bool suggest(Diagnostic& d, const std::string& word,
               const std::function<std::vector<std::string>()>& names) const;

  /// Elaborates the nodes and elements into `net`: each copied from `from` when it reads none of
  /// `moved`, else elaborated; with `into`, what each read is kept there.
  void elaborate_declarations(NetworkSpec& net, const ElaborationRecord* from,
                              const ParamReads& moved, ElaborationRecord* into);
  /// Notes that the value being evaluated read `reads` (when reads are recorded).
  void note_reads(const ParamReads& reads);
  /// Collects the reads of an evaluation while it lives (when reads are recorded).
  class Reading;

  void elaborate_node(const NodeDecl& d, NodeSpec& out);
  bool fill_keys(const ElementSchema& schema, ast::KeyList keys, FileId f, Span at,
                 const std::function<std::string()>& owner, ElementSpec& out);
  std::optional<ElementSpec> elaborate_element(const ElementDecl& d);
  std::optional<ElementSpec> elaborate_composite(const ElementDecl& d);
  void apply_param_overrides();
  void apply_key_settings(NetworkSpec& net);
  void drop_unresolved_lags(NetworkSpec& net);
  void finish(NetworkSpec& net);
  void apply_case(NetworkSpec& net);
  void apply_case_items(NetworkSpec& net, const std::vector<ast::CaseItem>& items,
                        const Scope* scope, std::set<std::string>& seen);
  void apply_setting(NetworkSpec& net, const ast::CaseAssign& a, std::set<std::string>& seen);
  void apply_override(NetworkSpec& net, const ast::CaseAssign& a, const Scope* scope);
  std::optional<std::pair<double, double>> case_range(const ast::Range& r, const Place& p, Span at);
  /// Counts `n` more iterations of the case's loops; false (reported at `at`) past the limit.
  bool afford_case_iterations(std::size_t n, Span at, Span mark);
  /// Records that the case sets OBJECT.KEY `name` at `mark`; false (reported) when it did before.
  bool first_setting(const std::string& name, Span at, Span mark);
  /// Reports the first listed output time after the case's duration, at that time.
  void check_output_times(const CaseSettings& s);
  // The data statement (lang/data_elaboration.cpp).
  void apply_data(NetworkSpec& net, const ast::CaseData& data, const Scope* scope,
                  std::set<std::string>& seen);
  const ast::CaseData* first_data_statement() const;
  std::optional<Unit> temperature_unit(const ast::UnitText& text, FileId f, Span at,
                                       const char* what);
  bool column_map(NetworkSpec& net, const ast::CaseData& data);
  void check_data(const NetworkSpec& net, Span at, Span mark, const std::optional<Unit>& unit);
  void initial_from_data(NetworkSpec& net);
  /// Warns about rows of the case's data file after its duration (read by check_data()).
  void warn_data_beyond_duration(const CaseSettings& s);

  const Model& m_;
  Reporter report_;
  const CaseDecl* case_;
  ParamValues overrides_;
  const Overrides* external_; // values set from outside the model
  bool check_data_;
  /// The time column of the case's data file and where the case names it.
  struct DataTimes {
    CsvTable table; ///< the time column only
    Span at;        ///< the data statement
    Span mark;      ///< its path
  };
  std::optional<DataTimes> data_times_;             ///< set by check_data()
  bool structural_ = false;                         // load time: params refused
  const Scope* context_ = nullptr;                  // scope of the declaration being elaborated
  bool saw_time_ = false;                           // the last evaluation used `time` or a signal
  std::unordered_map<ast::Index, Signal> embedded_; // signals of the expression being compiled
  std::optional<CaseDataFile> case_data_;           // set by case_data_file()
  bool case_data_resolved_ = false;
  const Place* constant_place_ = nullptr; // the place number() is evaluating for
  Span statement_at_;                     // the statement of the expression being elaborated
  std::vector<KeyReference> references_;  // values reading other keys, resolved last
  // "OBJECT.KEY" -> its entries in references_ (a lookup per key set or read instead of a scan of
  // every reference, which made models with many references quadratic)
  std::unordered_map<std::string, std::vector<std::size_t>> reference_of_;
  std::size_t resolve_depth_ = 0; // references being resolved, each through the next
  NetworkSpec* net_ = nullptr;    // the network, while references are resolved
  bool time_allowed_ = false;     // `time` may be used by the evaluation under way
  std::unordered_map<std::string_view, const ValueDecl*> value_decls_;
  std::unordered_map<std::string_view, Quantity> values_;
  std::unordered_map<std::string_view, std::pair<double, double>> ranges_;
  std::map<std::string, double> pending_params_;
  std::vector<std::string> evaluating_;
  bool reads_first_ = false; // evaluate_reads_first() is under way (it does not nest)
  std::set<std::string, std::less<>> used_;
  std::vector<std::optional<Quantity>> instance_values_; // per instance value slot, once
  std::vector<int> element_slot_; // per element declaration: index in the network, or -1
  // OBJECT.KEY the case sets: where it was set first, and whether setting it again was reported
  std::map<std::string, std::pair<Span, bool>> set_keys_;
  std::size_t case_iterations_ = 0;                 // iterations of the case's loops so far
  bool case_loops_cut_ = false;                     // the case's loops passed the limit and stopped
  std::set<const ast::CaseFor*> failed_case_loops_; // the case's loops with a wrong bound
  GeneratedPlaces generated_; // problems in loops and instances reported so far
  // Reads recorded (run_near() with a record): the evaluations under way, innermost
  // last, and what each top-level value and instance value slot read.
  bool recording_ = false;
  std::vector<ParamReads*> readers_;
  std::unordered_map<const ValueDecl*, ParamReads> value_reads_;
  std::vector<ParamReads> instance_reads_;
  std::unordered_map<const ValueDecl*, ParamReads> case_reads_; // a case's param settings
};

} // namespace thermnet::lang
