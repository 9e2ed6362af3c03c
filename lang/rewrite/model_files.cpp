#include "lang/rewrite/model_files.hpp"

#include "lang/parser.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

namespace thermnet::rewrite {

namespace {

namespace fs = std::filesystem;
namespace ast = lang::ast;

/// What a path literal names.
enum class PathKind { include, data, table, plugin };

/// A path literal written in a model file.
struct PathRef {
  std::uint32_t begin = 0;        ///< first byte of the literal (its opening quote)
  std::uint32_t end = 0;          ///< one past its closing quote
  std::string text;               ///< the path, unescaped
  PathKind kind = PathKind::data; ///< the statement it is written in
  bool include() const { return kind == PathKind::include; }
};

/// Collects the path literals of a file's statements.
struct PathCollector {
  std::vector<PathRef>& out;

  void add(const ast::String& s, PathKind kind) const {
    out.push_back({s.begin, s.end, s.text, kind});
  }
  /// The file names of the tables standing in a file's expressions.
  void tables(const ast::File& file) const {
    for (const auto& s : file.signals)
      if (const auto* t = std::get_if<ast::TableSignal>(&s); t && !t->case_data)
        add(t->file, PathKind::table);
  }
  void operator()(const ast::IncludeStmt& s) const { add(s.path, PathKind::include); }
  void operator()(const ast::PluginStmt& s) const { add(s.path, PathKind::plugin); }
  void operator()(const ast::NodeStmt&) const {}
  void operator()(const ast::ElementStmt&) const {}
  void operator()(const ast::CompositeStmt&) const {}
  void operator()(const ast::ForStmt& s) const {
    for (const auto& b : s.body)
      std::visit(*this, b);
  }
  void operator()(const ast::SubmodelStmt& s) const {
    for (const auto& b : s.body)
      std::visit(*this, b);
  }
  void items(const std::vector<ast::CaseItem>& items) const {
    for (const auto& item : items) {
      if (const auto* d = std::get_if<ast::CaseData>(&item))
        add(d->path, PathKind::data);
      else if (const auto* loop = std::get_if<ast::CaseFor>(&item))
        this->items(loop->items);
    }
  }
  void operator()(const ast::CaseStmt& s) const { items(s.items); }
  void operator()(const ast::ModelStmt&) const {}
  void operator()(const ast::ConstStmt&) const {}
  void operator()(const ast::ParamStmt&) const {}
  void operator()(const ast::Boxed<ast::RequireStmt>&) const {}
};

/// A model file's path literals and, for each include, the file it loaded.
struct FileRefs {
  std::vector<PathRef> refs;
  std::vector<std::optional<lang::FileId>> targets;
};

/// An absolute, normalised path with symlinks resolved as far as the path exists.
fs::path real_path(const fs::path& p) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(p, ec);
  if (!ec) return c;
  return fs::absolute(p, ec).lexically_normal();
}

fs::path directory_of(const fs::path& file) {
  return file.parent_path().empty() ? fs::path(".") : file.parent_path();
}

/// A path written in file `from` as the path it names.
fs::path resolve(const fs::path& from, const std::string& written) {
  const fs::path p(written);
  return p.is_absolute() ? p : directory_of(from) / p;
}

/// How a file at `target` is named from directory `dir`: relative when possible.
std::string path_from(const fs::path& dir, const fs::path& target) {
  const fs::path t = real_path(target);
  const fs::path rel = t.lexically_relative(real_path(dir));
  return (rel.empty() ? t : rel).generic_string();
}

/// A string literal of the language for a path (\" and \\ escaped).
std::string string_literal(const std::string& path) {
  if (path.find_first_of("\r\n") != std::string::npos)
    throw RewriteError(fmt::format("cannot name '{}' in a model file (line break)", path));
  std::string s = "\"";
  for (char c : path) {
    if (c == '"' || c == '\\') s += '\\';
    s += c;
  }
  return s + "\"";
}

/// The model files reachable from the root (root first) with their path literals, and every path
/// the model reads (its files and the files they name).
struct ModelFiles {
  std::vector<lang::FileId> order;
  std::map<lang::FileId, FileRefs> refs;
  std::set<fs::path> inputs;
};

ModelFiles collect_files(const lang::SourceManager& sources, lang::FileId root,
                         const std::vector<const ast::File*>& parsed = {}) {
  ModelFiles m;
  std::map<fs::path, lang::FileId> by_path;
  for (lang::FileId id = 0; id < sources.size(); ++id) {
    by_path.emplace(real_path(sources.path(id)), id);
    m.inputs.insert(real_path(sources.path(id)));
  }
  m.order.push_back(root);
  for (std::size_t i = 0; i < m.order.size(); ++i) {
    const lang::FileId f = m.order[i];
    const auto given = std::find_if(parsed.begin(), parsed.end(),
                                    [f](const ast::File* p) { return p->file_id == f; });
    std::optional<ast::File> own; // parsed here when not given (a 100,000-node file: 0.5 s)
    if (given == parsed.end()) {
      lang::DiagnosticEngine diags(sources);
      own.emplace(lang::parse_file(f, sources, diags));
    }
    const ast::File& file = own ? *own : **given;
    FileRefs info;
    for (const auto& s : file.statements)
      std::visit(PathCollector{info.refs}, s);
    PathCollector{info.refs}.tables(file);
    std::sort(info.refs.begin(), info.refs.end(),
              [](const PathRef& a, const PathRef& b) { return a.begin < b.begin; });
    for (const auto& r : info.refs) {
      const fs::path named = real_path(resolve(sources.path(f), r.text));
      std::optional<lang::FileId> target;
      if (r.include()) {
        if (auto it = by_path.find(named); it != by_path.end()) target = it->second;
        if (target && std::find(m.order.begin(), m.order.end(), *target) == m.order.end())
          m.order.push_back(*target);
      }
      m.inputs.insert(named);
      info.targets.push_back(target);
    }
    m.refs.emplace(f, std::move(info));
  }
  return m;
}

/// The files that change: the root, those declaring an updated param, and their includers.
std::set<lang::FileId> changed_files(const ModelFiles& m, lang::FileId root,
                                     const std::vector<ParamUpdate>& updates) {
  std::set<lang::FileId> changed{root};
  for (const auto& u : updates)
    if (m.refs.count(u.param.value_span.file)) changed.insert(u.param.value_span.file);
  for (bool grew = true; grew;) {
    grew = false;
    for (const auto& [f, info] : m.refs)
      if (!changed.count(f))
        for (const auto& t : info.targets)
          if (t && changed.count(*t)) {
            changed.insert(f);
            grew = true;
            break;
          }
  }
  return changed;
}

/// Whether a name may be chosen for a copy: not a symlink (dangling or not), which the copy would
/// be written through, perhaps out of the folder. (A directory, FIFO or device there is taken and
/// makes the write fail, writing nothing; a regular file is replaced.)
bool not_symlink(const fs::path& p) {
  std::error_code ec;
  return !fs::is_symlink(fs::symlink_status(p, ec));
}

/// Where each changed file goes: the root to `out`, the others beside it; never onto an input.
std::map<lang::FileId, fs::path> destinations(const lang::SourceManager& sources,
                                              const ModelFiles& m,
                                              const std::set<lang::FileId>& changed,
                                              lang::FileId root, const std::string& out) {
  const fs::path out_path(out);
  const fs::path out_key = real_path(out_path);
  if (m.inputs.count(out_key))
    throw RewriteError(fmt::format("-o '{}' would overwrite a file the model reads; write the "
                                   "calibrated model to a new file",
                                   out));
  std::map<lang::FileId, fs::path> dest{{root, out_path}};
  std::set<fs::path> taken = m.inputs;
  taken.insert(out_key);
  for (lang::FileId f : m.order) {
    if (f == root || !changed.count(f)) continue;
    const fs::path original(sources.path(f));
    const std::string stem = out_path.stem().string() + "." + original.stem().string();
    const std::string ext = original.extension().string();
    fs::path p = out_path.parent_path() / (stem + ext);
    for (int n = 2; taken.count(real_path(p)) || !not_symlink(p); ++n)
      p = out_path.parent_path() / fmt::format("{}-{}{}", stem, n, ext);
    taken.insert(real_path(p));
    dest.emplace(f, p);
  }
  return dest;
}

/// File `f` with its params updated and its path literals naming the copies (and, when it moves
/// to another directory, its relative paths re-expressed from there).
std::string rewritten_text(const lang::SourceManager& sources, lang::FileId f,
                           const std::vector<ParamUpdate>& updates, const FileRefs& info,
                           const std::set<lang::FileId>& changed,
                           const std::map<lang::FileId, fs::path>& dest,
                           std::vector<TextEdit> edits) {
  const fs::path from_dir = directory_of(sources.path(f));
  const fs::path to_dir = directory_of(dest.at(f));
  const bool moved = real_path(from_dir) != real_path(to_dir);
  const auto params = param_edits(sources, f, updates);
  edits.insert(edits.end(), params.begin(), params.end());
  for (std::size_t k = 0; k < info.refs.size(); ++k) {
    const PathRef& r = info.refs[k];
    std::optional<std::string> path;
    if (info.targets[k] && changed.count(*info.targets[k]))
      path = path_from(to_dir, dest.at(*info.targets[k]));
    else if (moved && fs::path(r.text).is_relative())
      path = path_from(to_dir, from_dir / r.text);
    if (path && *path != r.text) edits.push_back({r.begin, r.end, string_literal(*path)});
  }
  return apply_edits(sources.text(f), std::move(edits));
}

/// What a file named by a path literal is to the model.
const char* role_of(PathKind kind) {
  switch (kind) {
  case PathKind::include:
    return "the included file";
  case PathKind::data:
    return "the data file";
  case PathKind::table:
    return "the table file";
  case PathKind::plugin:
    return "the plugin";
  }
  return "the input";
}

} // namespace

std::vector<InputFile> files_read(const lang::SourceManager& sources, lang::FileId root,
                                  const std::vector<const ast::File*>& parsed) {
  const ModelFiles m = collect_files(sources, root, parsed);
  std::vector<InputFile> files;
  for (lang::FileId f : m.order)
    files.push_back({sources.path(f), f == root ? "the model" : role_of(PathKind::include)});
  for (lang::FileId f : m.order) {
    const FileRefs& info = m.refs.at(f);
    for (std::size_t k = 0; k < info.refs.size(); ++k)
      if (!info.targets[k]) // an include that was not loaded, or a data, table or plugin file
        files.push_back(
            {resolve(sources.path(f), info.refs[k].text).string(), role_of(info.refs[k].kind)});
  }
  return files;
}

std::vector<RewrittenFile> rewrite_model(const lang::SourceManager& sources, lang::FileId root,
                                         const std::vector<ParamUpdate>& updates,
                                         const std::string& out, std::vector<TextEdit> root_edits) {
  const ModelFiles m = collect_files(sources, root);
  const std::set<lang::FileId> changed = changed_files(m, root, updates);
  const std::map<lang::FileId, fs::path> dest = destinations(sources, m, changed, root, out);
  std::vector<RewrittenFile> result;
  for (lang::FileId f : m.order)
    if (changed.count(f))
      result.push_back({dest.at(f).string(),
                        rewritten_text(sources, f, updates, m.refs.at(f), changed, dest,
                                       f == root ? std::move(root_edits) : std::vector<TextEdit>{}),
                        f, f != root});
  return result;
}

} // namespace thermnet::rewrite
