// Loading a model: reading files, following includes, collecting declarations and checking that
// every name is unique in its namespace.

#include "lang/keywords.hpp"
#include "lang/model.hpp"
#include "lang/parser.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <unordered_map>

namespace thermnet::lang {

namespace fs = std::filesystem;

/// Builds a Model from its root file (friend of Model).
class ModelBuilder {
public:
  ModelBuilder(Model& m, SourceManager& sources, DiagnosticEngine& diags, const LoadOptions& opt)
      : m_(m), sources_(sources), diags_(diags), opt_(opt) {}

  bool load_root(const std::string& path) {
    std::string text, error;
    if (!read_file(path, text, error)) {
      Diagnostic d =
          DiagnosticEngine::make(DiagId::file_unreadable, std::nullopt, std::nullopt, path, error);
      d.file_hint = path;
      diags_.add(std::move(d));
      return false;
    }
    load_text(path, std::move(text));
    return true;
  }

  void load_root_text(const std::string& path, std::string text) {
    load_text(path, std::move(text));
  }

private:
  static bool read_file(const std::string& path, std::string& text, std::string& error) {
    if (auto e = read_text_file(path, text)) {
      error = *e;
      return false;
    }
    return true;
  }

  static std::string canonical(const std::string& path) {
    std::error_code ec;
    auto p = fs::weakly_canonical(fs::path(path), ec);
    return ec ? path : p.string();
  }

  void load_text(const std::string& path, std::string text) {
    FileId id = sources_.add(path, std::move(text));
    loaded_.insert(canonical(path));
    stack_.push_back(canonical(path));
    open_ids_.push_back(id);
    auto file = std::make_unique<ast::File>(parse_file(id, sources_, diags_));
    const ast::File& f = *file;
    m_.files_.push_back(std::move(file));
    m_.syntax_errors_ += f.syntax_errors;
    for (const auto& u : f.unparsed) {
      const std::string& head = u.head.name;
      if (!u.name.name.empty() && head != "model" && head != "include" && head != "plugin")
        m_.unparsed_names_.insert(u.name.name);
    }
    for (const auto& s : f.statements) {
      if (diags_.saturated()) {
        diags_.stop_early();
        break;
      }
      collect(s, id);
    }
    stack_.pop_back();
    open_ids_.pop_back();
  }

  std::string relative_to(FileId file, const std::string& p) const {
    fs::path path(p);
    if (path.is_absolute()) return p;
    return (fs::path(sources_.path(file)).parent_path() / path).lexically_normal().string();
  }

  Span span(FileId f, const ast::Tagged& t) const { return Span{f, t.begin, t.end}; }
  Span at(FileId f, const ast::Tagged& t) const { return Span{f, t.begin, t.begin}; }

  /// Reports a reserved name, and a duplicate with a note at the first definition (`previous`).
  /// A reserved name is reported, then kept: its uses must not cascade into more errors.
  void check_name(const char* what, const ast::Identifier& id, FileId f, const ast::Tagged& stmt,
                  const Span* previous) {
    if (is_keyword(id.name))
      diags_.report(DiagId::reserved_name, at(f, stmt), span(f, id), what, id.name);
    if (!previous) return;
    auto& d = diags_.report(DiagId::duplicate_name, at(f, stmt), span(f, id), what, id.name);
    d.notes.push_back(DiagnosticEngine::note(DiagId::previous_definition, *previous));
  }

  /// Registers a name in a namespace; false (and reported) when it is already defined.
  bool unique(std::unordered_map<std::string, Span>& names, const char* what,
              const ast::Identifier& id, FileId f, const ast::Tagged& stmt) {
    auto [it, fresh] = names.emplace(id.name, span(f, id));
    check_name(what, id, f, stmt, fresh ? nullptr : &it->second);
    return fresh;
  }

  /// unique() for nodes and elements: the Model's name index records the position in `decls`
  /// the declaration is about to take, so elaborations need no index of their own.
  template <typename Decl>
  bool unique_decl(std::unordered_map<std::string, int>& index, const std::vector<Decl>& decls,
                   const char* what, const ast::Identifier& id, FileId f, const ast::Tagged& stmt) {
    auto [it, fresh] = index.emplace(id.name, static_cast<int>(decls.size()));
    check_name(what, id, f, stmt,
               fresh ? nullptr : &decls[static_cast<std::size_t>(it->second)].name_span);
    return fresh;
  }

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
      b.m_.values_.push_back(
          ValueDecl{is_param, name.name, e, r, std::move(doc), f, b.span(f, s), b.span(f, name)});
    }
    void operator()(const ast::NodeStmt& s) const { node(false, s.name, s.keys, s.doc, s); }
    void operator()(const ast::BoundaryStmt& s) const { node(true, s.name, s.keys, s.doc, s); }
    void node(bool boundary, const ast::Identifier& name, const std::vector<ast::KeyValue>& keys,
              const std::optional<ast::String>& doc, const ast::Tagged& s) const {
      if (!b.unique_decl(b.m_.node_index_, b.m_.nodes_, boundary ? "boundary" : "node", name, f, s))
        return;
      b.m_.nodes_.push_back(NodeDecl{boundary, name.name, &keys, doc ? doc->text : "", f,
                                     b.span(f, s), b.span(f, name)});
    }
    void operator()(const ast::ElementStmt& s) const {
      if (!b.unique_decl(b.m_.element_index_, b.m_.elements_, "element", s.name, f, s)) return;
      b.m_.elements_.push_back(
          ElementDecl{&s, nullptr, s.name.name, f, b.span(f, s), b.span(f, s.name)});
    }
    void operator()(const ast::CompositeStmt& s) const {
      if (!b.unique_decl(b.m_.element_index_, b.m_.elements_, "element", s.name, f, s)) return;
      b.m_.elements_.push_back(
          ElementDecl{nullptr, &s, s.name.name, f, b.span(f, s), b.span(f, s.name)});
    }
    void operator()(const ast::CaseStmt& s) const {
      if (!b.unique(b.case_names_, "case", s.name, f, s)) return;
      b.m_.cases_.push_back(CaseDecl{&s, s.name.name, f, b.span(f, s), b.span(f, s.name)});
    }
  };

  void collect(const ast::Statement& s, FileId f) { boost::apply_visitor(Collector{*this, f}, s); }

  void include(const ast::IncludeStmt& s, FileId f) {
    std::string path = relative_to(f, s.path.text);
    std::string key = canonical(path);
    for (std::size_t i = 0; i < stack_.size(); ++i)
      if (stack_[i] == key) {
        // Name the chain as the user wrote it: the files from the one included again to here.
        std::string chain;
        for (std::size_t k = i; k < stack_.size(); ++k)
          chain += sources_.path(open_ids_[k]) + " -> ";
        diags_.report(DiagId::include_cycle, at(f, s), span(f, s.path), s.path.text,
                      chain + s.path.text);
        return;
      }
    if (loaded_.count(key)) return; // already included elsewhere: its declarations are in
    if (constexpr std::size_t max_depth = 64; stack_.size() >= max_depth) {
      diags_.report(DiagId::include_too_deep, at(f, s), span(f, s.path), s.path.text, max_depth);
      return;
    }
    std::string text, error;
    if (!read_file(path, text, error)) {
      diags_.report(DiagId::include_unreadable, at(f, s), span(f, s.path), s.path.text, error);
      return;
    }
    load_text(path, std::move(text));
  }

  Model& m_;
  SourceManager& sources_;
  DiagnosticEngine& diags_;
  const LoadOptions& opt_;
  std::vector<std::string> stack_;
  std::vector<FileId> open_ids_;
  std::set<std::string> loaded_;
  std::unordered_map<std::string, Span> value_names_, case_names_;
  bool model_seen_ = false;
};

std::unique_ptr<Model> Model::load(const std::string& path, const ElementCatalog& catalog,
                                   SourceManager& sources, DiagnosticEngine& diags,
                                   const LoadOptions& options) {
  auto m = std::unique_ptr<Model>(new Model());
  m->path_ = path;
  m->name_ = fs::path(path).stem().string();
  m->sources_ = &sources;
  m->catalog_ = &catalog;
  ModelBuilder b(*m, sources, diags, options);
  if (!b.load_root(path)) return nullptr;
  return m;
}

std::unique_ptr<Model> Model::from_text(const std::string& path, std::string text,
                                        const ElementCatalog& catalog, SourceManager& sources,
                                        DiagnosticEngine& diags, const LoadOptions& options) {
  auto m = std::unique_ptr<Model>(new Model());
  m->path_ = path;
  m->name_ = fs::path(path).stem().string();
  m->sources_ = &sources;
  m->catalog_ = &catalog;
  ModelBuilder b(*m, sources, diags, options);
  b.load_root_text(path, std::move(text));
  return m;
}

std::string Model::directory_of(FileId file) const {
  return fs::path(sources_->path(file)).parent_path().string();
}

std::vector<std::string> Model::case_names() const {
  std::vector<std::string> names;
  for (const auto& c : cases_)
    names.push_back(c.name);
  return names;
}

std::string Model::resolve_case(const std::string& name) const {
  if (name.empty()) {
    if (cases_.size() == 1) return cases_[0].name;
    if (cases_.empty()) return "default";
    for (const auto& c : cases_)
      if (c.name == "default") return c.name;
    std::string list;
    for (const auto& c : cases_)
      list += (list.empty() ? "" : ", ") + c.name;
    Diagnostic d;
    d.code = "choose-case";
    d.message =
        fmt::format("the model has {} cases ({}); choose one with --case", cases_.size(), list);
    d.file_hint = path_;
    throw ModelError(std::move(d));
  }
  for (const auto& c : cases_)
    if (c.name == name) return name;
  if (cases_.empty() && name == "default") return name;
  Diagnostic d;
  d.code = "unknown-case";
  d.message = fmt::format("the model has no case '{}'", name);
  d.file_hint = path_;
  if (auto s = closest_match(name, case_names()))
    d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *s));
  throw ModelError(std::move(d));
}

} // namespace thermnet::lang
