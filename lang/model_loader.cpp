// Loading a model: reading files, following includes, collecting declarations and checking that
// every name is unique in its namespace (the expansion of loops and instances and the resolution
// of terminals are in model_expansion.cpp).

#include "lang/model_builder.hpp"

#include "lang/elaborator.hpp"
#include "lang/keywords.hpp"
#include "lang/loop_iteration.hpp"
#include "lang/model.hpp"
#include "lang/parser.hpp"

#include <filesystem>
#include <map>
#include <set>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

namespace thermnet::lang {

namespace fs = std::filesystem;

/// Builds a Model from its root file (friend of Model).

bool ModelBuilder::load_root(const std::string& path) {
  std::string text, error;
  if (!read_file(path, text, error)) {
    Diagnostic d =
        DiagnosticEngine::make(DiagId::file_unreadable, std::nullopt, std::nullopt, path, error);
    d.file_hint = path;
    diags_.add(std::move(d));
    return false;
  }
  load_text(path, std::move(text));
  finish();
  return true;
}

void ModelBuilder::load_root_text(const std::string& path, std::string text) {
  load_text(path, std::move(text));
  finish();
}

bool ModelBuilder::read_file(const std::string& path, std::string& text, std::string& error) {
  if (auto e = read_text_file(path, text)) {
    error = *e;
    return false;
  }
  return true;
}

std::string ModelBuilder::canonical(const std::string& path) {
  std::error_code ec;
  auto p = fs::weakly_canonical(fs::path(path), ec);
  return ec ? path : p.string();
}

void ModelBuilder::load_text(const std::string& path, std::string text) {
  FileId id = sources_.add(path, std::move(text));
  const std::string key = canonical(path);
  loaded_.emplace(key, Span{});
  stack_.push_back(key);
  open_ids_.push_back(id);
  auto file = std::make_unique<ast::File>(parse_file(id, sources_, diags_));
  const ast::File& f = *file;
  m_.files_.push_back(std::move(file));
  m_.syntax_errors_ += f.syntax_errors;
  for (const auto& u : f.unparsed) {
    const std::string_view head = u.head.name;
    if (!u.name.name.empty() && head != "model" && head != "include" && head != "plugin")
      m_.unparsed_names_.emplace(u.name.name);
  }
  for (const auto& s : f.statements) {
    if (diags_.saturated()) {
      diags_.stop_early();
      break;
    }
    if (std::holds_alternative<ast::NodeStmt>(s) || std::holds_alternative<ast::ElementStmt>(s) ||
        std::holds_alternative<ast::CompositeStmt>(s) || std::holds_alternative<ast::ForStmt>(s))
      structure_.emplace_back(&s, id);
    else
      std::visit(Collector{*this, id}, s);
  }
  stack_.pop_back();
  open_ids_.pop_back();
}

std::string ModelBuilder::relative_to(FileId file, const std::string& p) const {
  fs::path path(p);
  if (path.is_absolute()) return p;
  return (fs::path(sources_.path(file)).parent_path() / path).lexically_normal().string();
}

void ModelBuilder::include(const ast::IncludeStmt& s, FileId f) {
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
  if (auto it = loaded_.find(key); it != loaded_.end()) {
    // Read before: its declarations are in, once (two files may share a library). The same
    // file including it twice most likely meant two copies, which is what submodels are for.
    if (it->second.end != 0 && it->second.file == f) {
      auto& d = diags_.report(DiagId::repeated_include, at(f, s), span(f, s.path), s.path.text);
      d.notes.push_back(
          DiagnosticEngine::note(DiagId::note_text, it->second, "first included here"));
    }
    return;
  }
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
  loaded_[key] = span(f, s.path);
}

void ModelBuilder::check_name(const char* what, std::string_view base, std::string_view full,
                              Span name_span, Span where, const Span* previous,
                              const Scope* scope) {
  if (is_keyword(base)) {
    Diagnostic d = DiagnosticEngine::make(DiagId::reserved_name, where, name_span, what, full);
    report(std::move(d), scope, false);
  }
  if (!previous) return;
  Diagnostic d = DiagnosticEngine::make(DiagId::duplicate_name, where, name_span, what, full);
  d.notes.push_back(DiagnosticEngine::note(DiagId::previous_definition, *previous));
  report(std::move(d), scope, false);
}

bool ModelBuilder::unique(std::unordered_map<std::string_view, Span>& names, const char* what,
                          const ast::Identifier& id, FileId f, const ast::Tagged& stmt) {
  auto [it, fresh] = names.emplace(id.name, span(f, id));
  check_name(what, id.name, id.name, span(f, id), at(f, stmt), fresh ? nullptr : &it->second,
             nullptr);
  return fresh;
}

void ModelBuilder::collect_submodel(const ast::SubmodelStmt& s, FileId f) {
  if (m_.catalog().find(s.name.name)) {
    diags_.report(DiagId::duplicate_name, at(f, s), span(f, s.name), "submodel", s.name.name)
        .message = fmt::format("submodel '{}' has the name of an element kind", s.name.name);
    return;
  }
  if (!unique(submodel_names_, "submodel", s.name, f, s)) return;
  SubmodelDecl& sub = m_.submodels_.emplace_back();
  sub.name = s.name.name;
  sub.stmt = &s;
  sub.file = f;
  sub.where = span(f, s);
  sub.name_span = span(f, s.name);
  std::unordered_map<std::string_view, Span> names;
  for (const auto& t : s.terminals)
    if (auto [it, fresh] = names.emplace(t.name, span(f, t)); !fresh)
      check_name("terminal", t.name, t.name, span(f, t), at(f, s), &it->second, nullptr);
  for (const auto& stmt : s.body) {
    const auto* p = std::get_if<ast::ParamStmt>(&stmt);
    const auto* c = std::get_if<ast::ConstStmt>(&stmt);
    if (!p && !c) continue;
    const ast::Identifier& id = p ? p->name : c->name;
    const ast::Tagged& tag = p ? static_cast<const ast::Tagged&>(*p) : *c;
    if (p && p->range) {
      diags_.report(DiagId::misplaced_statement, at(f, *p), span(f, *p->range),
                    fmt::format("param '{}' of submodel '{}' cannot have a range: declare a "
                                "ranged param at the top level and pass it to the instances "
                                "('{} u1 NODE {} = NAME')",
                                id.name, sub.name, sub.name, id.name));
      continue;
    }
    auto [it, fresh] = names.emplace(id.name, span(f, id));
    if (!fresh) {
      check_name(p ? "param" : "const", id.name, id.name, span(f, id), at(f, tag), &it->second,
                 nullptr);
      continue;
    }
    sub.values.push_back(ValueDecl{p != nullptr, std::string(id.name),
                                   p ? (p->value.valid() ? &p->value : nullptr) : &c->value,
                                   nullptr, p && p->doc ? p->doc->text : "", f, span(f, tag),
                                   span(f, id)});
  }
  m_.submodel_index_.emplace(sub.name, static_cast<int>(m_.submodels_.size() - 1));
}

void ModelBuilder::check_block(const std::vector<ast::Statement>& body, FileId f, bool in_loop,
                               const SubmodelDecl* sub, std::vector<std::string_view>& vars) {
  for (const auto& s : body) {
    const ast::Tagged& t = ast::tag_of(s);
    const char* word = std::visit(
        [](const auto& st) -> const char* {
          using T = std::decay_t<decltype(st)>;
          if constexpr (std::is_same_v<T, ast::ModelStmt>) return "model";
          if constexpr (std::is_same_v<T, ast::IncludeStmt>) return "include";
          if constexpr (std::is_same_v<T, ast::PluginStmt>) return "plugin";
          if constexpr (std::is_same_v<T, ast::CaseStmt>) return "case";
          if constexpr (std::is_same_v<T, ast::SubmodelStmt>) return "submodel";
          if constexpr (std::is_same_v<T, ast::Boxed<ast::RequireStmt>>) return "require";
          if constexpr (std::is_same_v<T, ast::ConstStmt>) return "const";
          if constexpr (std::is_same_v<T, ast::ParamStmt>) return "param";
          return nullptr;
        },
        s);
    const bool value =
        word && (std::string_view(word) == "const" || word == std::string_view("param"));
    if (word && (!value || in_loop)) {
      diags_.report(DiagId::misplaced_statement, at(f, t), Span{f, t.begin, t.begin + 1},
                    value ? fmt::format("a {} cannot be declared inside a for loop (it would be "
                                        "declared once per iteration); declare it outside",
                                        word)
                          : fmt::format("'{}' may stand only at the top level of a file, not "
                                        "inside a {}",
                                        word, in_loop ? "for loop" : "submodel"));
      continue;
    }
    if (const auto* loop = std::get_if<ast::ForStmt>(&s)) check_loop(*loop, f, sub, vars);
  }
}

void ModelBuilder::check_loop(const ast::ForStmt& loop, FileId f, const SubmodelDecl* sub,
                              std::vector<std::string_view>& vars) {
  const std::size_t outer = vars.size();
  for (const auto& r : loop.ranges) {
    const std::string_view v = r.var.name;
    const char* clash = nullptr;
    if (live_vars_.count(v))
      clash = "an enclosing loop's variable";
    else if (sub && sub->value_index(v) >= 0)
      clash = "a param or const of the submodel";
    else if (sub && sub->terminal_index(v) >= 0)
      clash = "a terminal of the submodel";
    else if (value_names_.count(v))
      clash = "a const or param of the model";
    else if (v == "pi" || v == "sigma" || is_keyword(v))
      clash = "a built-in name";
    if (clash) {
      diags_.report(DiagId::bad_loop, at(f, loop), span(f, r.var),
                    fmt::format("loop variable '{}' has the name of {}", v, clash));
      bad_loops_.insert(&loop); // not expanded: its names would mean two things
    }
    vars.push_back(v);
    live_vars_.insert(v);
  }
  check_block(loop.body, f, true, sub, vars);
  for (std::size_t k = outer; k < vars.size(); ++k)
    live_vars_.erase(live_vars_.find(vars[k]));
  vars.resize(outer);
}

void ModelBuilder::find_submodel_cycles() {
  const std::size_t n = m_.submodels_.size();
  std::vector<std::vector<SubmodelUse>> uses(n); // per submodel, its instances (in loops too)
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<const std::vector<ast::Statement>*> blocks{&m_.submodels_[i].stmt->body};
    while (!blocks.empty()) {
      const auto* block = blocks.back();
      blocks.pop_back();
      for (const auto& st : *block)
        if (const auto* e = std::get_if<ast::ElementStmt>(&st)) {
          if (auto it = m_.submodel_index_.find(e->kind.name); it != m_.submodel_index_.end())
            uses[i].push_back(SubmodelUse{it->second, e});
        } else if (const auto* loop = std::get_if<ast::ForStmt>(&st)) {
          blocks.push_back(&loop->body);
        }
    }
    std::sort(uses[i].begin(), uses[i].end(), [](const SubmodelUse& a, const SubmodelUse& b) {
      return a.stmt->begin < b.stmt->begin;
    });
  }
  enum : char { unseen, open, done };
  std::vector<char> state(n, unseen);
  std::vector<std::size_t> place(n);             // position on the path of an open submodel
  std::vector<std::pair<int, std::size_t>> path; // submodel, its next instance to follow
  for (std::size_t root = 0; root < n; ++root) {
    if (state[root] != unseen) continue;
    state[root] = open;
    path.assign(1, {static_cast<int>(root), 0});
    while (!path.empty() && !diags_.saturated()) {
      const auto i = static_cast<std::size_t>(path.back().first);
      if (path.back().second == uses[i].size()) {
        state[i] = done;
        path.pop_back();
        continue;
      }
      const SubmodelUse u = uses[i][path.back().second++];
      const auto j = static_cast<std::size_t>(u.sub);
      if (state[j] == unseen) {
        state[j] = open;
        place[j] = path.size();
        path.emplace_back(u.sub, 0);
      } else if (state[j] == open) {
        report_cycle(path, place[j], u, m_.submodels_[i].file);
      }
    }
  }
}

void ModelBuilder::report_cycle(const std::vector<std::pair<int, std::size_t>>& path,
                                std::size_t from, const SubmodelUse& u, FileId f) {
  const auto name = [&](std::size_t k) -> const std::string& {
    return m_.submodels_[static_cast<std::size_t>(path[k].first)].name;
  };
  const std::size_t length = path.size() - from;
  std::string chain;
  for (std::size_t k = from; k < path.size(); ++k) {
    cyclic_.insert(&m_.submodels_[static_cast<std::size_t>(path[k].first)]);
    if (length <= 8 || k < from + 3 || k >= path.size() - 3)
      chain += name(k) + " -> ";
    else if (k == from + 3)
      chain += fmt::format("... ({} more) -> ", length - 6);
  }
  const SubmodelDecl& target = m_.submodels_[static_cast<std::size_t>(u.sub)];
  report(DiagnosticEngine::make(DiagId::submodel_cycle, at(f, *u.stmt), span(f, u.stmt->kind),
                                target.name, chain + target.name),
         nullptr, true);
}

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

const SubmodelDecl* Model::submodel(std::string_view name) const {
  auto it = submodel_index_.find(name);
  return it == submodel_index_.end() ? nullptr : &submodels_[static_cast<std::size_t>(it->second)];
}

const Scope* Model::instance(std::string_view name) const {
  auto it = instance_index_.find(name);
  return it == instance_index_.end() ? nullptr : it->second;
}

const ast::File& Model::file(FileId id) const {
  for (const auto& f : files_)
    if (f->file_id == id) return *f;
  throw std::out_of_range("no such file in the model");
}

std::vector<std::string> Model::case_names() const {
  std::vector<std::string> names;
  for (const auto& c : cases_)
    names.push_back(c.name);
  return names;
}

std::vector<std::string> Model::run_case_names() const {
  std::vector<std::string> names = case_names();
  if (names.empty()) names.push_back("default");
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
