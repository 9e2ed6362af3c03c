#pragma once
/// A checked model: its files, declarations and cases; instantiated per case into NetworkSpecs.

#include "lang/ast.hpp"
#include "lang/diagnostics.hpp"
#include "lang/network_spec.hpp"
#include "lang/schema.hpp"
#include "lang/units.hpp"

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace thermnet::lang {

/// A model problem found while instantiating (the first error, with its location).
struct ModelError : std::runtime_error {
  /// Wraps a diagnostic.
  explicit ModelError(Diagnostic d) : std::runtime_error(d.message), diag(std::move(d)) {}
  Diagnostic diag; ///< what and where
};

/// A const or param declaration.
struct ValueDecl {
  bool is_param = false;             ///< param (true) or const
  std::string name;                  ///< its name
  const ast::Expr* expr = nullptr;   ///< value expression
  const ast::Range* range = nullptr; ///< calibration range (params)
  std::string doc;                   ///< description
  FileId file = 0;                   ///< declaring file
  Span where;                        ///< statement
  Span name_span;                    ///< the name
};

/// A node or boundary declaration.
struct NodeDecl {
  bool boundary = false;                            ///< boundary (true) or node
  std::string name;                                 ///< its name
  const std::vector<ast::KeyValue>* keys = nullptr; ///< C/T0 or T
  std::string doc;                                  ///< description
  FileId file = 0;                                  ///< declaring file
  Span where;                                       ///< statement
  Span name_span;                                   ///< the name
};

/// An element or series/parallel declaration.
struct ElementDecl {
  const ast::ElementStmt* element = nullptr;     ///< a plugin element, or
  const ast::CompositeStmt* composite = nullptr; ///< a series/parallel block
  std::string name;                              ///< its name
  FileId file = 0;                               ///< declaring file
  Span where;                                    ///< statement
  Span name_span;                                ///< the name
};

/// A case declaration.
struct CaseDecl {
  const ast::CaseStmt* stmt = nullptr; ///< the block
  std::string name;                    ///< its name
  FileId file = 0;                     ///< declaring file
  Span where;                          ///< statement
  Span name_span;                      ///< the name
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
  /// True when calibratable.
  bool ranged() const { return lo.has_value(); }
};

/// Param values overriding the declared ones, by name, in SI.
using ParamValues = std::map<std::string, double, std::less<>>;

/// How to load a model.
struct LoadOptions {
  /// Loads a plugin library named by a `plugin` statement; returns an error message or nothing.
  std::function<std::optional<std::string>(const std::string& path)> load_plugin;
};

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

  /// Elaborates a case (empty name: the only case or the implicit default) with param overrides;
  /// throws ModelError at the first problem.
  NetworkSpec instantiate(const std::string& case_name = "", const ParamValues& params = {}) const;

  /// Names of the declared cases, in order (empty when the model has none).
  std::vector<std::string> case_names() const;
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

  /// Declarations (for the elaborator and tools such as the language server).
  const std::vector<ValueDecl>& values() const { return values_; }
  /// Node and boundary declarations.
  const std::vector<NodeDecl>& nodes() const { return nodes_; }
  /// Element declarations.
  const std::vector<ElementDecl>& elements() const { return elements_; }
  /// Case declarations.
  const std::vector<CaseDecl>& cases() const { return cases_; }
  /// Directory of the file a declaration lives in (for relative data paths).
  std::string directory_of(FileId file) const;
  /// True when a statement that failed to parse meant to declare this name (references to it are
  /// not reported again).
  bool declared_by_unparsed(const std::string& name) const {
    return unparsed_names_.count(name) != 0;
  }
  /// Number of syntax errors in the model's files (whole-model warnings are unreliable then).
  std::size_t syntax_errors() const { return syntax_errors_; }
  /// Index in nodes() of the first node or boundary with this name, or -1.
  int node_index(const std::string& name) const {
    auto it = node_index_.find(name);
    return it == node_index_.end() ? -1 : it->second;
  }
  /// Index in elements() of the first element with this name, or -1.
  int element_index(const std::string& name) const {
    auto it = element_index_.find(name);
    return it == element_index_.end() ? -1 : it->second;
  }

private:
  friend class ModelBuilder;
  std::string path_;
  std::string name_;
  const SourceManager* sources_ = nullptr;
  const ElementCatalog* catalog_ = nullptr;
  std::vector<std::unique_ptr<ast::File>> files_;
  std::vector<ValueDecl> values_;
  std::vector<NodeDecl> nodes_;
  std::vector<ElementDecl> elements_;
  std::vector<CaseDecl> cases_;
  std::set<std::string> unparsed_names_;
  std::size_t syntax_errors_ = 0;
  // Name -> declaration index, filled while loading; shared by every elaboration.
  std::unordered_map<std::string, int> node_index_;
  std::unordered_map<std::string, int> element_index_;
};

} // namespace thermnet::lang
