// Loading a model: reading files, following includes, collecting declarations, expanding loops
// and submodel instances into one declaration per name, checking that every name is unique in its
// namespace, and resolving the nodes elements connect.

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
class ModelBuilder {
public:
  ModelBuilder(Model& m, SourceManager& sources, DiagnosticEngine& diags, const LoadOptions& opt)
      : m_(m), sources_(sources), diags_(diags), opt_(opt) {
    m_.max_case_iterations_ = opt.max_case_iterations;
  }

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
    finish();
    return true;
  }

  void load_root_text(const std::string& path, std::string text) {
    load_text(path, std::move(text));
    finish();
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

  // --- reading ----------------------------------------------------------------------------------

  void load_text(const std::string& path, std::string text) {
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

  std::string relative_to(FileId file, const std::string& p) const {
    fs::path path(p);
    if (path.is_absolute()) return p;
    return (fs::path(sources_.path(file)).parent_path() / path).lexically_normal().string();
  }

  static Span span(FileId f, const ast::Tagged& t) { return Span{f, t.begin, t.end}; }
  static Span at(FileId f, const ast::Tagged& t) { return Span{f, t.begin, t.begin}; }

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

  // --- names ------------------------------------------------------------------------------------

  /// Reports a reserved name, and a duplicate with a note at the first definition (`previous`).
  /// A reserved name is reported, then kept: its uses must not cascade into more errors.
  void check_name(const char* what, std::string_view base, std::string_view full, Span name_span,
                  Span where, const Span* previous, const Scope* scope) {
    if (is_keyword(base)) {
      Diagnostic d = DiagnosticEngine::make(DiagId::reserved_name, where, name_span, what, full);
      report(std::move(d), scope, false);
    }
    if (!previous) return;
    Diagnostic d = DiagnosticEngine::make(DiagId::duplicate_name, where, name_span, what, full);
    d.notes.push_back(DiagnosticEngine::note(DiagId::previous_definition, *previous));
    report(std::move(d), scope, false);
  }

  /// Registers a value or case name in its namespace; false (and reported) when already defined.
  bool unique(std::unordered_map<std::string_view, Span>& names, const char* what,
              const ast::Identifier& id, FileId f, const ast::Tagged& stmt) {
    auto [it, fresh] = names.emplace(id.name, span(f, id));
    check_name(what, id.name, id.name, span(f, id), at(f, stmt), fresh ? nullptr : &it->second,
               nullptr);
    return fresh;
  }

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

  void collect_submodel(const ast::SubmodelStmt& s, FileId f) {
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

  /// Reports statements that may not stand where they are, and loop variables that hide a name.
  void check_block(const std::vector<ast::Statement>& body, FileId f, bool in_loop,
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

  void check_loop(const ast::ForStmt& loop, FileId f, const SubmodelDecl* sub,
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

  /// An instance statement in a submodel's body, and the submodel it instantiates.
  struct SubmodelUse {
    int sub = -1;                           ///< index of the submodel instantiated
    const ast::ElementStmt* stmt = nullptr; ///< the instance statement
  };

  /// Reports every submodel that contains itself through a chain of instances, whether or not
  /// the model instantiates it, and marks it (its instances are not expanded). A depth-first
  /// search with its own stack: a chain of submodels may be as long as the file allows.
  void find_submodel_cycles() {
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

  /// Reports the cycle closed by instance `u` of the last submodel on `path`, which runs from
  /// position `from` of the path; long chains are shortened in the message.
  void report_cycle(const std::vector<std::pair<int, std::size_t>>& path, std::size_t from,
                    const SubmodelUse& u, FileId f) {
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

  // --- expansion ------------------------------------------------------------------------------

  void finish() {
    std::vector<std::string_view> vars;
    for (const auto& sub : m_.submodels_)
      check_block(sub.stmt->body, sub.file, false, &sub, vars);
    find_submodel_cycles();
    for (const auto& [stmt, f] : structure_)
      if (const auto* loop = std::get_if<ast::ForStmt>(stmt)) check_loop(*loop, f, nullptr, vars);
    elaborator_.emplace(
        Elaborator::structural(m_, [this](Diagnostic d) { report(std::move(d), nullptr, true); }));
    // A flat model declares one name per statement: size the indices once (robin-hood hashing
    // stays fast well above the default load factor of 0.5, and a bucket costs 12 bytes).
    std::size_t nodes = 0, elements = 0;
    for (const auto& [stmt, f] : structure_) {
      nodes += std::holds_alternative<ast::NodeStmt>(*stmt);
      elements += std::holds_alternative<ast::ElementStmt>(*stmt) ||
                  std::holds_alternative<ast::CompositeStmt>(*stmt);
    }
    m_.node_index_.reserve(nodes, 0.8f);
    m_.element_index_.reserve(elements, 0.8f);
    for (const auto& [stmt, f] : structure_) {
      if (stopped_ || diags_.saturated()) break;
      expand(*stmt, f, nullptr);
    }
    resolve();
    m_.truncated_ = stopped_;
    m_.structurally_used_ = elaborator_->used_names();
  }

  /// Counts one generated declaration or loop iteration; false once the limit is passed.
  bool count(FileId f, const ast::Tagged& where) {
    if (!affordable(1, f, where)) return false;
    ++work_;
    return true;
  }

  /// True when `n` more declarations or iterations stay within the limit; else reports that the
  /// model generates too much (at `where`) and stops the expansion. Ranges are checked this way
  /// before they run, so a huge one costs no time or memory.
  bool affordable(std::size_t n, FileId f, const ast::Tagged& where) {
    if (stopped_) return false;
    if (n <= opt_.max_generated - work_) return true; // work_ never passes the limit
    stopped_ = true;
    Diagnostic d = DiagnosticEngine::make(DiagId::too_much_generated, at(f, where), span(f, where),
                                          opt_.max_generated);
    if (!opt_.too_large_note.empty())
      d.notes.push_back(
          DiagnosticEngine::note(DiagId::note_text, std::nullopt, opt_.too_large_note));
    report(std::move(d), nullptr, true);
    return false;
  }

  void expand(const ast::Statement& s, FileId f, const Scope* scope) {
    if (const auto* n = std::get_if<ast::NodeStmt>(&s)) {
      declare_nodes(*n, f, scope);
    } else if (const auto* e = std::get_if<ast::ElementStmt>(&s)) {
      if (const SubmodelDecl* sub = m_.submodel(e->kind.name))
        instantiate(*e, *sub, f, scope);
      else
        declare_elements(e, nullptr, f, scope);
    } else if (const auto* c = std::get_if<ast::CompositeStmt>(&s)) {
      declare_elements(nullptr, c, f, scope);
    } else if (const auto* loop = std::get_if<ast::ForStmt>(&s);
               loop && !bad_loops_.count(loop) &&
               !failed_loops_.count({loop, scope ? scope->instance() : nullptr})) {
      Scope partial = Scope::loop(scope, f, loop->begin, loop->ranges);
      iterate(*loop, partial);
    }
    // Anything else in a body was reported by check_block (or is a submodel's param or const).
  }

  /// Runs the loop's body once per combination of its variables' values (iteratively: a header
  /// may name any number of variables). An iteration whose body declares nothing leaves no scope.
  void iterate(const ast::ForStmt& loop, Scope& partial) {
    const FileId f = partial.file;
    const auto bounds = [&](std::size_t k) -> std::optional<LoopBounds> {
      const ast::LoopRange& r = loop.ranges[k];
      try {
        const long lo = elaborator_->whole_number(r.lo, f, &partial, "the first value of a loop");
        const long hi = elaborator_->whole_number(r.hi, f, &partial, "the last value of a loop");
        // The whole range is counted before it runs: a huge one is refused at once.
        if (hi >= lo && !affordable(static_cast<std::size_t>(hi - lo) + 1, f, loop))
          return std::nullopt;
        return LoopBounds{lo, hi};
      } catch (const EvalError& e) {
        // Reported once: the loop runs no more, here or in the iterations of the loops around it
        // (a wrong bound inside 20 nested loops would otherwise be evaluated a million times).
        if (!e.diag.code.empty()) report(located(e.diag, f, loop), partial.parent, true);
        failed_loops_.emplace(&loop, partial.instance());
        return std::nullopt;
      }
    };
    const auto body = [&] {
      const std::size_t nodes = m_.nodes_.size(), elements = m_.elements_.size(),
                        scopes = m_.scopes_.size();
      const Scope& iteration = m_.scopes_.emplace_back(partial);
      for (const auto& s : loop.body) {
        if (stopped_) break;
        expand(s, f, &iteration);
      }
      // Nothing refers to the scope of an iteration that declared nothing: it is not kept.
      if (m_.nodes_.size() == nodes && m_.elements_.size() == elements &&
          m_.scopes_.size() == scopes + 1)
        m_.scopes_.pop_back();
      return !stopped_;
    };
    for_each_iteration(
        loop.ranges.size(), partial.values, bounds, [&] { return count(f, loop); }, body);
  }

  /// Every full name a declaration stands for: its instance's prefix and its name, once per
  /// combination of its index ranges (`p[1 .. 3]` is p[1], p[2], p[3]); false when an index is
  /// wrong (reported).
  bool declared_names(const ast::Ref& name, FileId f, const Scope* scope, const ast::Tagged& stmt,
                      std::vector<std::string>& out) {
    out.clear();
    const Scope* inst = scope ? scope->instance() : nullptr;
    std::string base = inst ? inst->prefix : std::string();
    base += name.id.name;
    if (name.plain()) {
      out.push_back(std::move(base));
      return true;
    }
    std::vector<std::pair<long, long>> ranges;
    try {
      for (const auto& item : name.index()) {
        const long lo = elaborator_->whole_number(item.lo, f, scope, "an index");
        const long hi = item.hi ? elaborator_->whole_number(*item.hi, f, scope, "an index") : lo;
        if (hi < lo) return true; // an empty range declares nothing
        ranges.emplace_back(lo, hi);
      }
    } catch (const EvalError& e) {
      if (!e.diag.code.empty()) report(located(e.diag, f, stmt), scope, true);
      return false;
    }
    // Every name is counted before one is made: a huge range is refused at once.
    std::size_t total = 1;
    for (const auto& r : ranges) {
      const auto n = static_cast<std::size_t>(r.second - r.first) + 1;
      total = total > opt_.max_generated / n ? opt_.max_generated + 1 : total * n;
    }
    if (!affordable(total, f, stmt)) return false;
    std::vector<long> at_index;
    for (const auto& r : ranges)
      at_index.push_back(r.first);
    for (;;) {
      if (!count(f, stmt)) return false;
      std::string n = base + '[';
      for (std::size_t i = 0; i < at_index.size(); ++i) {
        if (i) n += ',';
        n += std::to_string(at_index[i]);
      }
      out.push_back(n + ']');
      std::size_t i = at_index.size();
      while (i-- > 0) {
        if (at_index[i] < ranges[i].second) {
          ++at_index[i];
          break;
        }
        at_index[i] = ranges[i].first;
      }
      if (i == static_cast<std::size_t>(-1)) return true;
    }
  }

  void declare_nodes(const ast::NodeStmt& s, FileId f, const Scope* scope) {
    if (!declared_names(s.name, f, scope, s, names_)) return;
    const char* what = s.boundary ? "boundary" : "node";
    for (std::string& name : names_) {
      NodeDecl& d = m_.nodes_.emplace_back();
      d.stmt = &s;
      d.name = kept_name(s.name, scope, name);
      d.scope = scope;
      d.file = f;
      d.boundary = s.boundary;
      const int index = static_cast<int>(m_.nodes_.size() - 1);
      const int first = m_.node_index_.insert(index);
      std::optional<Span> previous;
      if (first >= 0) previous = m_.nodes_[static_cast<std::size_t>(first)].name_span();
      check_name(what, s.name.id.name, d.name, d.name_span(), at(f, s),
                 previous ? &*previous : nullptr, scope);
      if (first >= 0) m_.nodes_.pop_back();
    }
  }

  /// A declared name as the model keeps it: a plain name at the top level is the identifier in
  /// its file's text (the common case of big files); any other is copied to the model's store.
  std::string_view kept_name(const ast::Ref& ref, const Scope* scope, std::string_view name) {
    if (ref.plain() && !(scope && scope->instance())) return ref.id.name;
    return m_.name_text_.keep(name);
  }

  /// Registers an element's name (`index`) or an instance's (`instance`, its file and statement
  /// set) in the element namespace; false when taken.
  bool element_name(std::string_view name, int index, const Scope* instance, std::string_view base,
                    Span name_span, Span where, const Scope* scope) {
    // One hash lookup for the common case, a new element's name: it is entered at once and taken
    // out again if an instance has it.
    std::optional<Span> previous;
    bool entered = false;
    if (instance) {
      if (const int i = m_.element_index_.find(name); i >= 0)
        previous = m_.elements_[static_cast<std::size_t>(i)].name_span();
    } else if (const int i = m_.element_index_.insert(index); i >= 0) {
      previous = m_.elements_[static_cast<std::size_t>(i)].name_span();
    } else {
      entered = true;
    }
    if (!previous && !m_.instance_index_.empty())
      if (const Scope* other = m_.instance(name))
        previous = span(other->file, other->statement->name);
    check_name(instance ? "instance" : "element", base, name, name_span, where,
               previous ? &*previous : nullptr, scope);
    if (previous) {
      if (entered) m_.element_index_.erase(name);
      return false;
    }
    if (instance) m_.instance_index_.emplace(name, instance);
    return true;
  }

  void declare_elements(const ast::ElementStmt* e, const ast::CompositeStmt* c, FileId f,
                        const Scope* scope) {
    const ast::Tagged& s = e ? static_cast<const ast::Tagged&>(*e) : *c;
    const ast::Ref& name = e ? e->name : c->name;
    const ElementSchema* schema = nullptr;
    bool valid = true;
    if (e) {
      schema = kind_schema(e->kind.name);
      if (!schema) {
        Diagnostic d =
            DiagnosticEngine::make(DiagId::unknown_kind, at(f, s), span(f, e->kind), e->kind.name);
        std::vector<std::string> kinds = m_.catalog().kinds();
        for (const auto& sub : m_.submodels_)
          kinds.push_back(sub.name);
        if (auto k = closest_match(std::string(e->kind.name), kinds))
          d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *k));
        report(std::move(d), scope, true);
        valid = false;
      } else if (e->mean && !schema->observes) {
        report(DiagnosticEngine::make(
                   DiagId::wrong_terminals_text, at(f, s),
                   Span{f, e->nodes.front().begin, e->nodes.back().end},
                   fmt::format("only a sensor reads the mean of several nodes (sensor s mean(a, "
                               "b)); element kind '{}' takes {} terminal node(s)",
                               e->kind.name, schema->terminals)),
               scope, true);
        valid = false;
      } else if (!e->mean && static_cast<int>(e->nodes.size()) != schema->terminals) {
        Span mark = e->nodes.empty() ? span(f, e->name)
                                     : Span{f, e->nodes.front().begin, e->nodes.back().end};
        report(DiagnosticEngine::make(DiagId::wrong_terminals, at(f, s), mark, e->kind.name,
                                      schema->terminals, e->nodes.size()),
               scope, true);
        valid = false;
      }
    }
    if (!declared_names(name, f, scope, s, names_)) return;
    for (std::string& n : names_) {
      const int index = static_cast<int>(m_.elements_.size());
      ElementDecl& d = m_.elements_.emplace_back();
      d.element = e;
      d.composite = c;
      d.name = kept_name(name, scope, n);
      d.scope = scope;
      d.schema = schema;
      d.file = f;
      d.valid = valid;
      if (!element_name(d.name, index, nullptr, name.id.name, span(f, name), at(f, s), scope))
        m_.elements_.pop_back();
    }
  }

  /// The schema of an element kind, or nullptr; big files name the same kind many times in a row,
  /// so the last one found is kept (the catalog only gains kinds, never changes one).
  const ElementSchema* kind_schema(std::string_view kind) {
    if (last_schema_ && kind == last_kind_) return last_schema_;
    const ElementSchema* schema = m_.catalog().find(kind);
    if (schema) {
      last_kind_ = kind;
      last_schema_ = schema;
    }
    return schema;
  }

  /// Checks an instance's keys against its submodel's params (once per statement).
  void check_arguments(const ast::ElementStmt& s, const SubmodelDecl& sub, FileId f,
                       const Scope* scope, const std::string& name) {
    if (s.mean) {
      report(DiagnosticEngine::make(
                 DiagId::wrong_terminals_text, at(f, s),
                 Span{f, s.nodes.front().begin, s.nodes.back().end},
                 fmt::format("only a sensor reads the mean of several nodes; submodel '{}' takes "
                             "its {} terminal node(s) as a list",
                             sub.name, sub.stmt->terminals.size())),
             scope, true);
      return;
    }
    if (s.nodes.size() != sub.stmt->terminals.size()) {
      Span mark =
          s.nodes.empty() ? span(f, s.name) : Span{f, s.nodes.front().begin, s.nodes.back().end};
      report(DiagnosticEngine::make(DiagId::instance_terminals, at(f, s), mark, sub.name,
                                    sub.stmt->terminals.size(), s.nodes.size()),
             scope, true);
    }
    std::vector<std::string> params;
    for (const auto& v : sub.values)
      if (v.is_param) params.push_back(v.name);
    std::set<std::string_view> given;
    for (const auto& kv : s.keys) {
      const int k = sub.value_index(kv.key.name);
      if (k < 0 || !sub.values[static_cast<std::size_t>(k)].is_param) {
        Diagnostic d = DiagnosticEngine::make(DiagId::unknown_key, at(f, s), span(f, kv.key),
                                              fmt::format("submodel '{}'", sub.name), kv.key.name);
        d.message = fmt::format("submodel '{}' has no param '{}'", sub.name, kv.key.name);
        if (auto m = closest_match(std::string(kv.key.name), params))
          d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *m));
        else
          d.notes.push_back(DiagnosticEngine::note(
              DiagId::note_text, std::nullopt,
              params.empty() ? fmt::format("submodel '{}' has no params", sub.name)
                             : fmt::format("its params: {}", fmt::join(params, ", "))));
        report(std::move(d), scope, true);
      } else if (!given.insert(kv.key.name).second) {
        report(
            DiagnosticEngine::make(DiagId::duplicate_key, at(f, s), span(f, kv.key), kv.key.name),
            scope, true);
      }
    }
    for (const auto& v : sub.values)
      if (v.is_param && !v.expr && !given.count(v.name))
        report(DiagnosticEngine::make(DiagId::missing_argument, at(f, s), span(f, s.name), name,
                                      sub.name, v.name),
               scope, true);
  }

  void instantiate(const ast::ElementStmt& s, const SubmodelDecl& sub, FileId f,
                   const Scope* scope) {
    if (!declared_names(s.name, f, scope, s, names_)) return;
    std::vector<std::string> names = std::move(names_);
    for (std::string& name : names) {
      if (stopped_) return;
      Scope& inst = m_.scopes_.emplace_back();
      inst.prefix = name + '.';
      inst.name = std::move(name);
      inst.file = f;
      inst.statement = &s;
      // The instance's name is registered as a view of the scope's own copy, which stays put.
      if (!element_name(inst.name, -1, &inst, s.name.id.name, span(f, s.name), at(f, s), scope)) {
        m_.scopes_.pop_back();
        continue;
      }
      check_arguments(s, sub, f, scope, inst.name);
      inst.kind = Scope::Kind::instance;
      inst.parent = scope;
      inst.where = span(f, s);
      inst.submodel = &sub;
      inst.terminals.assign(sub.stmt->terminals.size(), -1);
      inst.slot = m_.instance_slots_;
      m_.instance_slots_ += sub.values.size();
      if (cyclic_.count(&sub)) continue; // reported at its definition; its body is not expanded
      if (depth_ >= max_instance_depth) {
        report(DiagnosticEngine::make(DiagId::submodel_too_deep, at(f, s), span(f, s.kind),
                                      inst.name, sub.name, max_instance_depth),
               nullptr, true);
        continue;
      }
      ++depth_;
      for (const auto& stmt : sub.stmt->body) {
        if (stopped_) break;
        expand(stmt, sub.file, &inst);
      }
      --depth_;
    }
  }

  // --- resolution -----------------------------------------------------------------------------

  /// Resolves the terminals of instances (outer ones first: they were created first), then those
  /// of elements, to node indices.
  void resolve() {
    for (Scope& s : m_.scopes_) {
      if (s.kind != Scope::Kind::instance) continue;
      const auto& refs = s.statement->nodes;
      for (std::size_t k = 0; k < refs.size() && k < s.terminals.size(); ++k)
        if (auto n = elaborator_->resolve_node(refs[k], s.file, s.parent,
                                               Span{s.file, s.where.begin, s.where.begin}))
          s.terminals[k] = *n;
    }
    const auto refs_of = [](const ElementDecl& d) -> const auto& {
      return d.element ? d.element->nodes : d.composite->nodes;
    };
    std::size_t count = 0;
    for (const ElementDecl& d : m_.elements_)
      count += refs_of(d).size();
    auto& terminals = m_.terminals_;
    terminals.reserve(count); // exactly: the declarations' spans view this array
    for (ElementDecl& d : m_.elements_) {
      const std::size_t first = terminals.size();
      const auto& refs = refs_of(d);
      if (!d.valid) { // its error is reported; its links still count for the topology warnings
        for (const auto& r : refs)
          terminals.push_back(elaborator_->find_node(r, d.file, d.scope));
      } else {
        const Span start{d.file, d.where().begin, d.where().begin};
        for (const auto& r : refs) {
          // A plain name at the top level is looked up directly (the common case of big files).
          int n = d.scope || !r.plain() ? -1 : m_.node_index(r.id.name);
          if (n < 0) n = elaborator_->resolve_node(r, d.file, d.scope, start).value_or(-1);
          terminals.push_back(n);
        }
      }
      d.nodes = std::span<const int>(terminals.data() + first, refs.size());
    }
  }

  // --- reporting ------------------------------------------------------------------------------

  /// A problem of an expression, reported at the start of the statement it stands in.
  static Diagnostic located(Diagnostic d, FileId f, const ast::Tagged& stmt) {
    if (!d.mark) d.mark = d.at;
    d.at = at(f, stmt);
    return d;
  }

  /// Reports a problem found while expanding: with notes naming the iteration and instance, once
  /// per place (later iterations repeat it); `structural` problems make declarations unusable,
  /// and instantiate() throws the first of them.
  void report(Diagnostic d, const Scope* scope, bool structural) {
    // (a repetition is dropped before its notes are made: a loop's millions of iterations)
    if (!reported_.first(d, scope)) return;
    add_scope_notes(d, scope);
    if (structural && d.severity == Severity::error && !m_.load_error_) m_.load_error_ = d;
    diags_.add(std::move(d));
  }

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
