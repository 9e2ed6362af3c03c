#pragma once
/// The builder of a Model from its files (internal to lang/: model_loader.cpp reads, names and
/// collects; model_expansion.cpp expands loops and instances, resolves terminals and reports).

#include "lang/elaborator.hpp"
#include "lang/model.hpp"

#include <cstddef>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

namespace thermnet::lang {

/// Builds a Model from its root file (friend of Model).
class ModelBuilder {
public:
  /// A builder of `m`, reporting into `diags`.
  ModelBuilder(Model& m, SourceManager& sources, DiagnosticEngine& diags, const LoadOptions& opt)
      : m_(m), sources_(sources), diags_(diags), opt_(opt) {
    m_.max_case_iterations_ = opt.max_case_iterations;
  }

  /// Reads the root file and everything it includes; false when the file cannot be read.
  bool load_root(const std::string& path);
  /// The same from the root file's text (an editor's buffer).
  void load_root_text(const std::string& path, std::string text);

private:
  /// Reads a file into `text`; false with `error` set when it cannot be read.
  static bool read_file(const std::string& path, std::string& text, std::string& error);

  /// The path made canonical (the path itself when that fails).
  static std::string canonical(const std::string& path);
  // --- reading ----------------------------------------------------------------------------------

  /// Parses one file's text and collects its statements (following its includes).
  void load_text(const std::string& path, std::string text);
  /// A path as written in `file`, relative to that file's folder.
  std::string relative_to(FileId file, const std::string& p) const;

  /// The whole of a tagged piece of text.
  static Span span(FileId f, const ast::Tagged& t) { return Span{f, t.begin, t.end}; }
  /// The start of a tagged piece of text.
  static Span at(FileId f, const ast::Tagged& t) { return Span{f, t.begin, t.begin}; }

  /// Follows an include (refused in a cycle, past 64 levels or unreadable; a file read before is
  /// not read again).
  void include(const ast::IncludeStmt& s, FileId f);
  // --- names ------------------------------------------------------------------------------------

  /// Reports a reserved name, and a duplicate with a note at the first definition (`previous`).
  /// A reserved name is reported, then kept: its uses must not cascade into more errors.
  void check_name(const char* what, std::string_view base, std::string_view full, Span name_span,
                  Span where, const Span* previous, const Scope* scope);

  /// Registers a value or case name in its namespace; false (and reported) when already defined.
  bool unique(std::unordered_map<std::string_view, Span>& names, const char* what,
              const ast::Identifier& id, FileId f, const ast::Tagged& stmt);

  // --- collecting the top level ---------------------------------------------------------------

  struct Collector {
    ModelBuilder& b;
    FileId f;

    void operator()(const ast::ModelStmt& s) const {
      if (b.model_seen_) {
        b.diags_.report(DiagId::duplicate_model, b.at(f, s), b.span(f, s));
        return;
      }
      b.model_seen_ = true;
      b.m_.name_ = s.name.name;
    }
    void operator()(const ast::IncludeStmt& s) const { b.include(s, f); }
    void operator()(const ast::PluginStmt& s) const {
      std::string path = b.relative_to(f, s.path.text);
      std::optional<std::string> err =
          b.opt_.load_plugin ? b.opt_.load_plugin(path)
                             : std::optional<std::string>("this tool does not load plugins");
      if (err)
        b.diags_.report(DiagId::plugin_error, b.at(f, s), b.span(f, s.path), s.path.text, *err);
    }
    void operator()(const ast::ConstStmt& s) const {
      value(false, s.name, &s.value, nullptr, {}, s);
    }
    void operator()(const ast::ParamStmt& s) const {
      value(true, s.name, &s.value, s.range ? &*s.range : nullptr, s.doc ? s.doc->text : "", s);
    }
    void value(bool is_param, const ast::Identifier& name, const ast::Expr* e, const ast::Range* r,
               std::string doc, const ast::Tagged& s) const {
      if (name.name == "pi" || name.name == "sigma") {
        b.diags_.report(DiagId::builtin_name, b.at(f, s), b.span(f, name), name.name);
        return;
      }
      if (!b.unique(b.value_names_, is_param ? "param" : "const", name, f, s)) return;
      b.m_.values_.push_back(ValueDecl{is_param, std::string(name.name), e, r, std::move(doc), f,
                                       b.span(f, s), b.span(f, name)});
    }
    void operator()(const ast::CaseStmt& s) const {
      if (!b.unique(b.case_names_, "case", s.name, f, s)) return;
      b.m_.cases_.push_back(
          CaseDecl{&s, std::string(s.name.name), f, b.span(f, s), b.span(f, s.name)});
    }
    void operator()(const ast::SubmodelStmt& s) const { b.collect_submodel(s, f); }
    void operator()(const ast::Boxed<ast::RequireStmt>& s) const {
      b.m_.requirements_.push_back(RequirementDecl{&*s, f, b.span(f, *s)});
    }
    // Nodes, elements, instances and loops are expanded once every file is read.
    void operator()(const ast::NodeStmt&) const {}
    void operator()(const ast::ElementStmt&) const {}
    void operator()(const ast::CompositeStmt&) const {}
    void operator()(const ast::ForStmt&) const {}
  };

  /// Registers a submodel definition and its params.
  void collect_submodel(const ast::SubmodelStmt& s, FileId f);
  /// Reports statements that may not stand where they are, and loop variables that hide a name.
  void check_block(const std::vector<ast::Statement>& body, FileId f, bool in_loop,
                   const SubmodelDecl* sub, std::vector<std::string_view>& vars);

  /// Reports loop variables that hide a name (an enclosing loop's, a param, a terminal, a keyword).
  void check_loop(const ast::ForStmt& loop, FileId f, const SubmodelDecl* sub,
                  std::vector<std::string_view>& vars);

  /// An instance statement in a submodel's body, and the submodel it instantiates.
  struct SubmodelUse {
    int sub = -1;                           ///< index of the submodel instantiated
    const ast::ElementStmt* stmt = nullptr; ///< the instance statement
  };

  /// Reports every submodel that contains itself through a chain of instances, whether or not
  /// the model instantiates it, and marks it (its instances are not expanded). A depth-first
  /// search with its own stack: a chain of submodels may be as long as the file allows.
  void find_submodel_cycles();

  /// Reports the cycle closed by instance `u` of the last submodel on `path`, which runs from
  /// position `from` of the path; long chains are shortened in the message.
  void report_cycle(const std::vector<std::pair<int, std::size_t>>& path, std::size_t from,
                    const SubmodelUse& u, FileId f);

  // --- expansion ------------------------------------------------------------------------------

  /// After the last file: checks blocks and cycles, expands the structure and resolves terminals.
  void finish();
  /// Counts one generated declaration or loop iteration; false once the limit is passed.
  bool count(FileId f, const ast::Tagged& where);

  /// True when `n` more declarations or iterations stay within the limit; else reports that the
  /// model generates too much (at `where`) and stops the expansion. Ranges are checked this way
  /// before they run, so a huge one costs no time or memory.
  bool affordable(std::size_t n, FileId f, const ast::Tagged& where);

  /// Expands one statement of the structure in `scope` (loops and instances recursively).
  void expand(const ast::Statement& s, FileId f, const Scope* scope);
  /// Runs the loop's body once per combination of its variables' values (iteratively: a header
  /// may name any number of variables). An iteration whose body declares nothing leaves no scope.
  void iterate(const ast::ForStmt& loop, Scope& partial);

  /// Every full name a declaration stands for: its instance's prefix and its name, once per
  /// combination of its index ranges (`p[1 .. 3]` is p[1], p[2], p[3]); false when an index is
  /// wrong (reported).
  bool declared_names(const ast::Ref& name, FileId f, const Scope* scope, const ast::Tagged& stmt,
                      std::vector<std::string>& out);

  /// Declares the nodes a node or boundary statement stands for.
  void declare_nodes(const ast::NodeStmt& s, FileId f, const Scope* scope);
  /// A declared name as the model keeps it: a plain name at the top level is the identifier in
  /// its file's text (the common case of big files); any other is copied to the model's store.
  std::string_view kept_name(const ast::Ref& ref, const Scope* scope, std::string_view name);

  /// Registers an element's name (`index`) or an instance's (`instance`, its file and statement
  /// set) in the element namespace; false when taken.
  bool element_name(std::string_view name, int index, const Scope* instance, std::string_view base,
                    Span name_span, Span where, const Scope* scope);

  /// Declares the elements (or the composite) a statement stands for.
  void declare_elements(const ast::ElementStmt* e, const ast::CompositeStmt* c, FileId f,
                        const Scope* scope);

  /// The schema of an element kind, or nullptr; big files name the same kind many times in a row,
  /// so the last one found is kept (the catalog only gains kinds, never changes one).
  const ElementSchema* kind_schema(std::string_view kind);

  /// Checks an instance's keys against its submodel's params (once per statement).
  void check_arguments(const ast::ElementStmt& s, const SubmodelDecl& sub, FileId f,
                       const Scope* scope, const std::string& name);

  /// Expands an instance of a submodel: its params bound, its body under the instance's prefix.
  void instantiate(const ast::ElementStmt& s, const SubmodelDecl& sub, FileId f,
                   const Scope* scope);

  // --- resolution -----------------------------------------------------------------------------

  /// Resolves the terminals of instances (outer ones first: they were created first), then those
  /// of elements, to node indices.
  void resolve();

  // --- reporting ------------------------------------------------------------------------------

  /// A problem of an expression, reported at the start of the statement it stands in.
  static Diagnostic located(Diagnostic d, FileId f, const ast::Tagged& stmt);

  /// Reports a problem found while expanding: with notes naming the iteration and instance, once
  /// per place (later iterations repeat it); `structural` problems make declarations unusable,
  /// and instantiate() throws the first of them.
  void report(Diagnostic d, const Scope* scope, bool structural);

  Model& m_;
  SourceManager& sources_;
  DiagnosticEngine& diags_;
  const LoadOptions& opt_;
  std::vector<std::string> stack_;
  std::vector<FileId> open_ids_;
  std::map<std::string, Span> loaded_; // canonical path -> the include that read it
  std::unordered_map<std::string_view, Span> value_names_, case_names_, submodel_names_;
  std::vector<std::pair<const ast::Statement*, FileId>> structure_; // top-level, in order
  std::string_view last_kind_;                 // the kind kind_schema() found last
  const ElementSchema* last_schema_ = nullptr; // and its schema
  std::optional<Elaborator> elaborator_;
  std::set<const SubmodelDecl*> cyclic_; // submodels that contain themselves (reported)
  std::unordered_multiset<std::string_view> live_vars_; // variables of the loops being checked
  std::size_t depth_ = 0;                   // instances being expanded, one inside the other
  std::vector<std::string> names_;          // scratch: the names of one declaration
  std::set<const ast::ForStmt*> bad_loops_; // loops whose variables hide another name
  // Loops with a wrong bound, by the instance they expand in (nullptr: the top level).
  std::set<std::pair<const ast::ForStmt*, const Scope*>> failed_loops_;
  GeneratedPlaces reported_; // problems in loops and instances, reported once per place
  std::size_t work_ = 0;
  bool stopped_ = false;
  bool model_seen_ = false;
};

} // namespace thermnet::lang
