#pragma once
/// A checked model: its files, declarations and cases; instantiated per case into NetworkSpecs.

#include "lang/ast.hpp"
#include "lang/diagnostics.hpp"
#include "lang/name_index.hpp"
#include "lang/network_spec.hpp"
#include "lang/schema.hpp"
#include "lang/table_cache.hpp"
#include "lang/text_store.hpp"
#include "lang/units.hpp"

#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_map>
#include <vector>

namespace thermnet::lang {

/// A model problem found while instantiating (the first error, with its location).
struct ModelError : std::runtime_error {
  /// Wraps a diagnostic.
  explicit ModelError(Diagnostic d) : std::runtime_error(d.message), diag(std::move(d)) {}
  Diagnostic diag; ///< what and where
};

/// A const or param declaration (at the top level, or local to a submodel).
struct ValueDecl {
  bool is_param = false;             ///< param (true) or const
  std::string name;                  ///< its name
  const ast::Expr* expr = nullptr;   ///< value expression (nullptr: a submodel param without one)
  const ast::Range* range = nullptr; ///< calibration range (params)
  std::string doc;                   ///< description
  FileId file = 0;                   ///< declaring file
  Span where;                        ///< statement
  Span name_span;                    ///< the name
};

struct SubmodelDecl;

/// Where a generated declaration stands: a loop iteration or a submodel instance, inside the
/// scopes around it. Declarations at the model's top level have no scope (nullptr).
struct Scope {
  /// What the scope is.
  enum class Kind : std::uint8_t { loop, instance };
  Kind kind = Kind::loop;        ///< loop iteration or instance
  const Scope* parent = nullptr; ///< the scope around it (nullptr: the top level)
  FileId file = 0;               ///< file of the `for` or instance statement
  Span where;                    ///< the `for` header or the instance statement
  // A loop iteration:
  const std::vector<ast::LoopRange>* ranges = nullptr; ///< the loop's variables
  std::vector<long> values;                            ///< their values in this iteration
  // An instance:
  const SubmodelDecl* submodel = nullptr;      ///< what is instantiated
  std::string name;                            ///< the instance's full name (`u1`, `a.u[2]`)
  std::string prefix;                          ///< prefix of inner names (`u1.`)
  const ast::ElementStmt* statement = nullptr; ///< the instance statement (its keys are args)
  std::vector<int> terminals;                  ///< node of each terminal (-1: unresolved)
  std::size_t slot = 0;                        ///< first value slot of the instance (elaboration)

  /// The scope of one iteration of a loop whose header starts at `begin` in `file`, inside
  /// `parent`; its variables' values are filled in by the caller as it iterates.
  static Scope loop(const Scope* parent, FileId file, std::uint32_t begin,
                    const std::vector<ast::LoopRange>& ranges);
  /// The innermost instance this scope belongs to (itself for an instance), or nullptr.
  const Scope* instance() const;
  /// The value of a loop variable visible here (in loops up to the instance), if any.
  std::optional<long> variable(std::string_view name) const;
};

/// Adds to a diagnostic the notes that say in which loop iterations and submodel instances it
/// arose ("in iteration i = 3, j = 7", "in instance 'u1' of submodel 'box'"), innermost first.
void add_scope_notes(Diagnostic& d, const Scope* scope);

/// The places (code, file, start, marked start) of the problems reported inside loops and
/// instances, where later iterations and instances repeat them: each is reported once.
class GeneratedPlaces {
public:
  /// False for a repetition: d arose in a loop or instance (`scope`, or d.generated) at a place
  /// seen before; true otherwise (every problem outside them).
  bool first(const Diagnostic& d, const Scope* scope);
  /// True when a problem like d (its code at its mark, whatever its statement) arose in a loop
  /// or instance before: d, not yet placed at its statement, most likely repeats it.
  bool seen(const Diagnostic& d, const Scope* scope) const;

private:
  // (code, mark's file and offset, statement's file and offset): seen() reads the first three
  std::set<std::tuple<std::string, FileId, std::uint32_t, FileId, std::uint32_t>> seen_;
};

/// A submodel definition: its terminals, params, local consts and body.
struct SubmodelDecl {
  std::string name;                        ///< used like an element kind
  const ast::SubmodelStmt* stmt = nullptr; ///< the definition
  std::vector<ValueDecl> values;           ///< its params and consts, in order
  FileId file = 0;                         ///< declaring file
  Span where;                              ///< statement
  Span name_span;                          ///< the name
  /// Index in `values` of a param or const, or -1.
  int value_index(std::string_view n) const;
  /// Index of a terminal, or -1.
  int terminal_index(std::string_view n) const;
};

/// A node or boundary declaration (one per generated name). Spans, keys and description are
/// read from the statement, which the model keeps: a large netlist has one declaration per line.
struct NodeDecl {
  const ast::NodeStmt* stmt = nullptr; ///< the declaring statement
  std::string_view name;               ///< its full name (`p[3]`, `u1.pcb`), kept by the model
  const Scope* scope = nullptr;        ///< loop iteration or instance, if any
  FileId file = 0;                     ///< declaring file
  bool boundary = false;               ///< boundary (true) or node

  /// C/T0 or T, as written.
  const auto& keys() const { return stmt->keys; }
  /// The description, or an empty text.
  std::string_view doc() const { return stmt->doc ? std::string_view(stmt->doc->text) : ""; }
  /// The statement.
  Span where() const { return Span{file, stmt->begin, stmt->end}; }
  /// The name as written (with its index list).
  Span name_span() const { return Span{file, stmt->name.begin, stmt->name.end}; }
};

/// An element or series/parallel declaration (one per generated name); its spans are read from
/// the statement.
struct ElementDecl {
  const ast::ElementStmt* element = nullptr;     ///< a plugin element, or
  const ast::CompositeStmt* composite = nullptr; ///< a series/parallel block
  std::string_view name;                         ///< its full name, kept by the model
  const Scope* scope = nullptr;                  ///< loop iteration or instance, if any
  const ElementSchema* schema = nullptr;         ///< the kind's schema (plugin elements)
  /// Resolved terminals (-1: unresolved), one per terminal written; they live in the model.
  std::span<const int> nodes;
  FileId file = 0;   ///< declaring file
  bool valid = true; ///< false when its kind, terminals or names are wrong (reported at load)

  /// The statement.
  Span where() const;
  /// The name as written (with its index list).
  Span name_span() const;
};
/// A case declaration.
struct CaseDecl {
  const ast::CaseStmt* stmt = nullptr; ///< the block
  std::string name;                    ///< its name
  FileId file = 0;                     ///< declaring file
  Span where;                          ///< statement
  Span name_span;                      ///< the name
};

/// A `require` statement (at the top level of a file).
struct RequirementDecl {
  const ast::RequireStmt* stmt = nullptr; ///< the statement
  FileId file = 0;                        ///< declaring file
  Span where;                             ///< statement
};

/// A param as calibration sees it (values in SI).
struct ParamInfo {
  std::string name;             ///< param name
  double value = 0.0;           ///< declared value, SI
  std::optional<double> lo;     ///< range low end, SI (ranged params)
  std::optional<double> hi;     ///< range high end, SI
  std::optional<Dimension> dim; ///< dimension (none for a bare number)
  std::string doc;              ///< description
  FileId file = 0;              ///< declaring file
  Span value_span;              ///< the value expression (for rewriting the model)
  std::string case_name;        ///< the case of a start temperature calibrated per case
  /// True when calibratable.
  bool ranged() const { return lo.has_value(); }
};

/// Param values overriding the declared ones, by name, in SI.
using ParamValues = std::map<std::string, double, std::less<>>;

/// A key of a node, boundary or element given a value from outside the model (`--set
/// NAME.KEY=VALUE`).
struct KeySetting {
  std::string object; ///< node, boundary or element, by full name
  std::string key;    ///< one of its keys (not a node-valued one)
  double value = 0.0; ///< SI (K for a temperature); a signal key becomes this constant
  std::string option; ///< the setting as the user wrote it, for messages
};

/// Values set from outside the model for a run (`--set`): they take precedence over the model's
/// declarations and over its cases' settings.
struct Overrides {
  ParamValues params;                   ///< params, SI
  std::vector<std::string> param_texts; ///< the param settings as written, for messages
  std::vector<KeySetting> keys;         ///< node, boundary and element keys, applied in order
  /// True when nothing is set.
  bool empty() const { return params.empty() && keys.empty(); }
};

/// A value set from outside the model that the model cannot take: an unknown name, a key of the
/// wrong kind, a value out of range or in conflict with the model.
struct OverrideError : std::invalid_argument {
  /// A message naming the option; `d` locates the model statement it conflicts with, if any.
  explicit OverrideError(const std::string& message, std::optional<Diagnostic> d = std::nullopt)
      : std::invalid_argument(message), diag(std::move(d)) {}
  std::optional<Diagnostic> diag; ///< the model's diagnostic, with a note naming the settings
};

/// Most submodel instances nested one inside another (a deeper chain is an error).
inline constexpr std::size_t max_instance_depth = 64;

/// How to load a model.
struct LoadOptions {
  /// Loads a plugin library named by a `plugin` statement; returns an error message or nothing.
  std::function<std::optional<std::string>(const std::string& path)> load_plugin;
  /// Most declarations and loop iterations loops and submodels may generate (a bound on the work
  /// a small file can ask for, in time and memory); counted before each range runs.
  std::size_t max_generated = 5'000'000;
  /// Most iterations the loops of one case may run, all together (counted before each range runs).
  std::size_t max_case_iterations = 1'000'000;
  /// A note added to the error of a model that generates more (empty: none).
  std::string too_large_note;
};

struct ElaborationRecord;

/// A parsed model with its declarations; instantiate() elaborates one case into a NetworkSpec.
class Model {
public:
  /// Reads, parses and collects a model and its includes; syntax and declaration problems go to
  /// diags. Returns nullptr only when the root file cannot be read.
  static std::unique_ptr<Model> load(const std::string& path, const ElementCatalog& catalog,
                                     SourceManager& sources, DiagnosticEngine& diags,
                                     const LoadOptions& options = {});

  /// Like load(), but with the root file's text given in memory under `path` (includes and data
  /// files are still read relative to it); never returns nullptr.
  static std::unique_ptr<Model> from_text(const std::string& path, std::string text,
                                          const ElementCatalog& catalog, SourceManager& sources,
                                          DiagnosticEngine& diags, const LoadOptions& options = {});

  /// Checks everything (every case, data files, topology) and reports all problems, warnings
  /// included.
  void lint(DiagnosticEngine& diags) const;

  /// Elaborates a case (empty name: the only case or the implicit default) with param overrides
  /// (over the values set from outside; a case's own setting of a param keeps precedence over
  /// them) and the values set from outside the model; throws ModelError at the first problem.
  NetworkSpec instantiate(const std::string& case_name = "", const ParamValues& params = {}) const;

  /// The network of a case without param overrides, elaborated once and shared (lint() elaborates
  /// every case and keeps those without errors); throws ModelError.
  std::shared_ptr<const NetworkSpec> network(const std::string& case_name = "") const;
  /// The network of a case moved out of the cache when nothing else holds it (no copy of a large
  /// network for a single run), else instantiate(case_name).
  NetworkSpec take_network(const std::string& case_name = "") const;

  /// The schema of key `key` of node, boundary or element `object`, to be set from outside the
  /// model; throws OverrideError naming `option` (unknown object or key, with a suggestion; a
  /// node-valued key; a key of a series/parallel block or of a submodel instance).
  const KeySchema& settable_key(std::string_view object, std::string_view key,
                                const std::string& option) const;
  /// Makes every later instantiate(), network(), take_network() and params() use these values
  /// (after lint(): the model file is checked without them). Elaborates every case with them and
  /// throws OverrideError when one cannot take them.
  void set_overrides(Overrides overrides);
  /// The values set from outside the model (empty unless set_overrides() was called).
  const Overrides& overrides() const { return overrides_; }
  /// Elaborates a case like instantiate(), with `overrides` in place of the model's own.
  NetworkSpec instantiate(const std::string& case_name, const ParamValues& params,
                          const Overrides& overrides) const;
  /// instantiate(case_name, params), keeping in `record` what instantiate_near() elaborates
  /// from (null when it cannot serve: a value that reads another key).
  NetworkSpec instantiate_recorded(const std::string& case_name, const ParamValues& params,
                                   std::shared_ptr<const ElaborationRecord>& record) const;
  /// instantiate(from.case_name, params), elaborated from a record: only the nodes and elements
  /// that read a param whose value differs from the record's are evaluated again. With `record`,
  /// keeps the result's record there as instantiate_recorded() does.
  NetworkSpec instantiate_near(const ElaborationRecord& from, const ParamValues& params,
                               std::shared_ptr<const ElaborationRecord>* record = nullptr) const;

  /// Names of the declared cases, in order (empty when the model has none).
  std::vector<std::string> case_names() const;
  /// The cases a run over the whole model covers: the declared ones, or "default" without any.
  std::vector<std::string> run_case_names() const;
  /// The case to use for an optional name: the named one, the only one, or "default"; throws
  /// ModelError.
  std::string resolve_case(const std::string& name) const;
  /// Every param with its declared value and range, in declaration order; throws ModelError on bad
  /// values.
  std::vector<ParamInfo> params() const;
  /// The model's name (from `model NAME`, else the file stem).
  const std::string& name() const { return name_; }
  /// The root file's path.
  const std::string& path() const { return path_; }
  /// The sources the model was read from.
  const SourceManager& sources() const { return *sources_; }
  /// The element catalog it was checked against.
  const ElementCatalog& catalog() const { return *catalog_; }

  /// Top-level const and param declarations (for the elaborator and tools such as the language
  /// server).
  const std::vector<ValueDecl>& values() const { return values_; }
  /// Node and boundary declarations, one per generated name, in order.
  const std::deque<NodeDecl>& nodes() const { return nodes_; }
  /// Element declarations, one per generated name, in order.
  const std::deque<ElementDecl>& elements() const { return elements_; }
  /// Case declarations.
  const std::vector<CaseDecl>& cases() const { return cases_; }
  /// Submodel definitions.
  const std::deque<SubmodelDecl>& submodels() const { return submodels_; }
  /// The `require` statements, in order.
  const std::vector<RequirementDecl>& requirements() const { return requirements_; }
  /// Loop iterations and instances the declarations stand in.
  const std::deque<Scope>& scopes() const { return scopes_; }
  /// The submodel instance of a full name (`u1`, `a.u[2]`), or nullptr.
  const Scope* instance(std::string_view name) const;
  /// The submodel of a name, or nullptr.
  const SubmodelDecl* submodel(std::string_view name) const;
  /// Number of value slots the instances need (their params and consts), for elaboration.
  std::size_t instance_slots() const { return instance_slots_; }
  /// The files of the model, in the order they were read.
  const std::vector<std::unique_ptr<ast::File>>& files() const { return files_; }
  /// The syntax tree of a file of the model.
  const ast::File& file(FileId id) const;
  /// Directory of the file a declaration lives in (for relative data paths).
  std::string directory_of(FileId file) const;
  /// True when a statement that failed to parse meant to declare this name (references to it are
  /// not reported again).
  bool declared_by_unparsed(std::string_view name) const {
    return unparsed_names_.find(name) != unparsed_names_.end();
  }
  /// Number of syntax errors in the model's files (whole-model warnings are unreliable then).
  std::size_t syntax_errors() const { return syntax_errors_; }
  /// Index in nodes() of the node or boundary with this full name, or -1.
  int node_index(std::string_view name) const { return node_index_.find(name); }
  /// Index in elements() of the element with this full name, or -1.
  int element_index(std::string_view name) const { return element_index_.find(name); }
  /// The CSV files the model's tables and data statements read, parsed once per file.
  TableCache& tables() const { return tables_; }
  /// True when a value reads the case's data file (`table(data, ...)`) or its clock (a table of
  /// absolute times): each case's network is then elaborated on its own.
  bool reads_case_data() const;
  /// The first error that made a declaration unusable while loading (an unknown kind or node,
  /// wrong terminals, a bad loop or index), which instantiate() throws; empty when there is none.
  const std::optional<Diagnostic>& load_error() const { return load_error_; }
  /// Most iterations the loops of one case may run, all together (LoadOptions).
  std::size_t max_case_iterations() const { return max_case_iterations_; }

private:
  friend class ModelBuilder;
  void remember(const std::string& case_name, NetworkSpec net) const;
  /// The declared case of that name, or nullptr (the implicit default case).
  const CaseDecl* find_case(std::string_view name) const;
  /// Elaborates the case `name` (resolved) with `overrides`: from `from` as instantiate_near()
  /// does, or in full without it; keeps the result's record in `record` when given.
  NetworkSpec elaborate_near(const std::string& name, const ElaborationRecord* from,
                             const ParamValues& params,
                             std::shared_ptr<const ElaborationRecord>* record,
                             const Overrides& overrides) const;

  std::string path_;
  std::string name_;
  const SourceManager* sources_ = nullptr;
  const ElementCatalog* catalog_ = nullptr;
  std::vector<std::unique_ptr<ast::File>> files_;
  std::vector<ValueDecl> values_;
  std::deque<SubmodelDecl> submodels_;
  std::deque<Scope> scopes_;
  std::deque<NodeDecl> nodes_;
  std::deque<ElementDecl> elements_;
  std::vector<int> terminals_; // every ElementDecl::nodes, reserved once (the spans stay valid)
  TextStore name_text_;        // generated node and element names (a plain name views its file)
  std::vector<CaseDecl> cases_;
  std::vector<RequirementDecl> requirements_;
  std::set<std::string, std::less<>> unparsed_names_;
  std::size_t syntax_errors_ = 0;
  std::size_t instance_slots_ = 0;
  bool truncated_ = false; // loops or instances were cut short at the generation limit
  std::size_t max_case_iterations_ = LoadOptions{}.max_case_iterations; // from the LoadOptions
  std::optional<Diagnostic> load_error_;
  Overrides overrides_; // values set from outside the model (`--set`)
  std::set<std::string, std::less<>> structurally_used_; // consts used by loops and indices
  // Name -> declaration index, filled while loading and shared by every elaboration; the names
  // are read from the declarations (a deque never moves them).
  NameIndex<std::deque<NodeDecl>> node_index_{nodes_};
  NameIndex<std::deque<ElementDecl>> element_index_{elements_};
  std::unordered_map<std::string_view, int> submodel_index_;
  std::unordered_map<std::string_view, const Scope*> instance_index_; // names viewed in the scopes
  mutable TableCache tables_;
  // Networks of cases without param overrides, elaborated once per run and shared.
  mutable std::mutex cache_mutex_;
  mutable std::map<std::string, std::shared_ptr<NetworkSpec>> cache_;
};

} // namespace thermnet::lang
