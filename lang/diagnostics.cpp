/// The diagnostic engine and its renderers (compiler-style text, JSON, SARIF 2.1.0).

#include "lang/diagnostics.hpp"

#include "lang/display_text.hpp"
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <map>
#include <tuple>

namespace thermnet::lang {

namespace {

// The kinds table, generated from the same X-macro as the DiagId enum so that both stay in
// the same order by construction.
constexpr DiagKind kKinds[] = {
#define DIAG(id, sev, code, fmtstr) DiagKind{Severity::sev, code, fmtstr},
#include "lang/diagnostic_kinds.def"
#undef DIAG
};

// ---------------------------------------------------------------------------------------
// Shared helpers

const char* severity_name(Severity s) {
  switch (s) {
  case Severity::note:
    return "note";
  case Severity::warning:
    return "warning";
  case Severity::error:
    return "error";
  }
  return "error";
}

bool is_continuation(char c) {
  return (static_cast<unsigned char>(c) & 0xC0) == 0x80;
}

std::size_t count_code_points(std::string_view s) {
  std::size_t n = 0;
  for (char c : s)
    n += !is_continuation(c);
  return n;
}

// Moves `pos` forward by up to `n` code points, never past `end`.
std::size_t advance_cp(std::string_view s, std::size_t pos, std::size_t end, std::size_t n) {
  for (; n > 0 && pos < end; --n) {
    ++pos;
    while (pos < end && is_continuation(s[pos]))
      ++pos;
  }
  return pos;
}

// Moves `pos` back by up to `n` code points, never before `begin`.
std::size_t retreat_cp(std::string_view s, std::size_t pos, std::size_t begin, std::size_t n) {
  for (; n > 0 && pos > begin; --n) {
    --pos;
    while (pos > begin && is_continuation(s[pos]))
      --pos;
  }
  return pos;
}

// Where a diagnostic is reported: its own `at`, else its mark (a diagnostic given only a
// range still has a position), else nothing (file-level problem).
std::optional<Span> location_of(const Diagnostic& d) {
  return d.at ? d.at : d.mark;
}

// A span is only usable when it names a file the engine knows; anything else is rendered
// as file-less rather than crashing in the middle of error reporting.
std::optional<Span> valid(const SourceManager& sm, std::optional<Span> s) {
  if (s && s->file < sm.size()) return s;
  return std::nullopt;
}

// The resolved position of a diagnostic: a span, or a name to print instead (file_hint,
// inherited by notes, or "thermnet").
struct Place {
  std::optional<Span> at;
  std::optional<Span> mark;
  std::string hint;
};

Place place_of(const SourceManager& sm, const Diagnostic& d) {
  Place p;
  p.at = valid(sm, location_of(d));
  if (p.at) p.mark = valid(sm, d.mark).value_or(*p.at);
  p.hint = d.file_hint;
  return p;
}

// Notes without a location of their own point where their parent points.
Place place_of_note(const SourceManager& sm, const Diagnostic& note, const Place& parent) {
  Place p = place_of(sm, note);
  if (!p.at) {
    p.at = parent.at;
    p.mark = parent.mark;
    if (p.hint.empty()) p.hint = parent.hint;
  }
  return p;
}

// ---------------------------------------------------------------------------------------
// Text rendering

// Lines longer than this many code points are shown as a window around the mark.
constexpr std::size_t kMaxLineWidth = 200;
// Window geometry: context kept before the mark's start, and total width shown.
constexpr std::size_t kWindowBefore = 80;
constexpr std::size_t kWindowWidth = 160;

struct Palette {
  const char* bold = "";
  const char* reset = "";
  const char* caret = "";
  const char* error = "";
  const char* warning = "";
  const char* note = "";
};

Palette make_palette(bool color) {
  if (!color) return {};
  // Clang's scheme; notes in cyan rather than clang's bold black, which vanishes on dark
  // terminals.
  return Palette{"\x1b[1m", "\x1b[0m", "\x1b[1;32m", "\x1b[1;31m", "\x1b[1;35m", "\x1b[1;36m"};
}

const char* severity_color(const Palette& p, Severity s) {
  switch (s) {
  case Severity::note:
    return p.note;
  case Severity::warning:
    return p.warning;
  case Severity::error:
    return p.error;
  }
  return p.error;
}

// Source text is printed verbatim except that tabs and other control characters become one
// space each: a tab would otherwise expand to a terminal-dependent width and break caret
// alignment (columns count a tab as one), and raw control bytes could drive the terminal.
void append_sanitized(std::string& out, std::string_view s) {
  for (char c : s) {
    const auto u = static_cast<unsigned char>(c);
    out += (u < 0x20 || u == 0x7F) ? ' ' : c;
  }
}

void render_snippet(std::string& out, const SourceManager& sm, const Span& mark,
                    const Palette& pal) {
  const std::string_view text = sm.text(mark.file);
  const std::size_t begin = std::min<std::size_t>(mark.begin, text.size());
  const std::size_t end = std::clamp<std::size_t>(mark.end, begin, text.size());
  const std::string_view line = sm.line_text(mark.file, sm.line_col(mark.file, mark.begin).line);
  const std::size_t line_start = static_cast<std::size_t>(line.data() - text.data());
  const std::size_t line_end = line_start + line.size();
  // A mark starting in the line terminator points just past the last character; a mark
  // spanning lines is underlined to the end of its first line.
  const std::size_t mark_begin = std::min(begin, line_end);
  const std::size_t mark_end = std::clamp(end, mark_begin, line_end);

  // Decide whether the line needs a window; counting stops early so a 100 MB line costs
  // nothing here beyond the first few hundred bytes.
  const bool long_line = line.size() > kMaxLineWidth &&
                         advance_cp(text, line_start, line_end, kMaxLineWidth) < line_end;
  std::size_t show_begin = line_start;
  std::size_t show_end = line_end;
  if (long_line) {
    show_begin = retreat_cp(text, mark_begin, line_start, kWindowBefore);
    show_end = advance_cp(text, show_begin, line_end, kWindowWidth);
  }
  const bool prefix = show_begin > line_start;
  const bool suffix = show_end < line_end;

  if (prefix) out += "...";
  append_sanitized(out, text.substr(show_begin, show_end - show_begin));
  if (suffix) out += "...";
  out += '\n';

  const std::size_t pad =
      (prefix ? 3 : 0) + count_code_points(text.substr(show_begin, mark_begin - show_begin));
  const std::size_t shown_end = std::min(mark_end, show_end);
  const std::size_t width = shown_end > mark_begin
                                ? count_code_points(text.substr(mark_begin, shown_end - mark_begin))
                                : 0;
  out += std::string(pad, ' ');
  out += pal.caret;
  out += '^';
  if (width > 1) out += std::string(width - 1, '~');
  out += pal.reset;
  out += '\n';
}

void render_one(std::string& out, const SourceManager& sm, const Diagnostic& d, const Place& pl,
                bool own_location, const Palette& pal) {
  out += pal.bold;
  if (pl.at) {
    const LineCol lc = sm.line_col(pl.at->file, pl.at->begin);
    out += fmt::format("{}:{}:{}: ", escape_for_display(sm.path(pl.at->file)), lc.line, lc.column);
  } else {
    out += pl.hint.empty() ? std::string("thermnet") : escape_for_display(pl.hint);
    out += ": ";
  }
  out += pal.reset;
  out += severity_color(pal, d.severity);
  out += severity_name(d.severity);
  out += ": ";
  out += pal.reset;
  out += pal.bold;
  out += escape_for_display(d.message);
  // Notes carry the generic code "note"; only errors and warnings name their kind.
  if (d.severity != Severity::note && !d.code.empty()) out += fmt::format(" [{}]", d.code);
  out += pal.reset;
  out += '\n';
  if (own_location && pl.mark) render_snippet(out, sm, *pl.mark, pal);
}

void render_tree(std::string& out, const SourceManager& sm, const Diagnostic& d, const Place& pl,
                 bool own_location, const Palette& pal) {
  render_one(out, sm, d, pl, own_location, pal);
  for (const Diagnostic& n : d.notes) {
    const Place np = place_of_note(sm, n, pl);
    // Only a note with a location of its own shows a snippet; an inherited one would just
    // repeat the parent's.
    render_tree(out, sm, n, np, valid(sm, location_of(n)).has_value(), pal);
  }
}

// ---------------------------------------------------------------------------------------
// JSON rendering

nlohmann::json json_of(const SourceManager& sm, const Diagnostic& d, const Place& pl) {
  nlohmann::json j;
  if (pl.at) {
    const LineCol b = sm.line_col(pl.at->file, pl.at->begin);
    const Span mark = pl.mark ? *pl.mark : *pl.at;
    const LineCol e = sm.line_col(mark.file, std::max(mark.end, mark.begin));
    j["file"] = escape_for_display(sm.path(pl.at->file));
    j["line"] = b.line;
    j["column"] = b.column;
    j["end_line"] = e.line;
    j["end_column"] = e.column;
  } else {
    // About a whole file (unreadable, ...): its start, so positions stay 1-based (cli.md).
    j["file"] = escape_for_display(pl.hint);
    j["line"] = 1;
    j["column"] = 1;
    j["end_line"] = 1;
    j["end_column"] = 1;
  }
  j["severity"] = severity_name(d.severity);
  j["code"] = d.code;
  j["message"] = escape_for_display(d.message);
  nlohmann::json notes = nlohmann::json::array();
  for (const Diagnostic& n : d.notes)
    notes.push_back(json_of(sm, n, place_of_note(sm, n, pl)));
  j["notes"] = std::move(notes);
  return j;
}

// Messages quote user input (names, paths) that may not be valid UTF-8; nlohmann would
// throw on such strings, so invalid bytes are replaced by U+FFFD instead.
std::string dump(const nlohmann::json& j) {
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

// ---------------------------------------------------------------------------------------
// SARIF rendering

// A path as a URI reference (RFC 3986): forward slashes, relative paths kept relative,
// absolute paths as file:// URIs, and everything outside the path character set
// percent-encoded. ':' is encoded in relative paths so "a:b.tnet" is not read as a scheme.
std::string path_to_uri(const std::string& path) {
  std::string p = path;
  std::replace(p.begin(), p.end(), '\\', '/');
  const bool drive = p.size() >= 2 && std::isalpha(static_cast<unsigned char>(p[0])) && p[1] == ':';
  const bool absolute = !p.empty() && p[0] == '/';
  std::string out;
  std::size_t i = 0;
  if (drive) {
    out = "file:///";
    out += p.substr(0, 2);
    i = 2;
  } else if (absolute) {
    out = "file://";
  }
  for (; i < p.size(); ++i) {
    const auto c = static_cast<unsigned char>(p[i]);
    const bool keep = std::isalnum(c) ||
                      std::string_view("-._~!$&'()*+,;=@/").find(static_cast<char>(c)) !=
                          std::string_view::npos ||
                      (c == ':' && (drive || absolute));
    if (keep) {
      out += static_cast<char>(c);
    } else {
      out += fmt::format("%{:02X}", c);
    }
  }
  return out;
}

const char* sarif_level(Severity s) {
  return severity_name(s);
}

class SarifBuilder {
public:
  explicit SarifBuilder(const SourceManager& sm) : sm_(sm) {
    // Every source file is an artifact, at the index equal to its FileId.
    for (FileId f = 0; f < sm.size(); ++f)
      add_artifact(sm.path(f));
  }

  nlohmann::json result(const Diagnostic& d) {
    const Place pl = place_of(sm_, d);
    nlohmann::json r;
    r["ruleId"] = d.code;
    r["ruleIndex"] = rule_index(d.code);
    r["level"] = sarif_level(d.severity);
    r["message"] = {{"text", escape_for_display(d.message)}};
    if (auto loc = physical(pl))
      r["locations"] = nlohmann::json::array({{{"physicalLocation", *loc}}});
    nlohmann::json related = nlohmann::json::array();
    collect_notes(d, pl, related);
    if (!related.empty()) r["relatedLocations"] = std::move(related);
    return r;
  }

  nlohmann::json rules() const {
    nlohmann::json rs = nlohmann::json::array();
    for (const std::string& id : rule_ids_)
      rs.push_back({{"id", id}});
    return rs;
  }

  nlohmann::json artifacts() const {
    nlohmann::json as = nlohmann::json::array();
    for (const std::string& uri : artifact_uris_)
      as.push_back({{"location", {{"uri", uri}}}});
    return as;
  }

private:
  std::size_t add_artifact(const std::string& path) {
    const std::string uri = path_to_uri(path);
    const auto [it, inserted] = artifact_index_.emplace(uri, artifact_uris_.size());
    if (inserted) artifact_uris_.push_back(uri);
    return it->second;
  }

  std::size_t rule_index(const std::string& code) {
    const auto [it, inserted] = rule_index_.emplace(code, rule_ids_.size());
    if (inserted) rule_ids_.push_back(code);
    return it->second;
  }

  // The physicalLocation of a place, or none for a file-less diagnostic without a hint.
  std::optional<nlohmann::json> physical(const Place& pl) {
    if (pl.at) {
      const std::string& path = sm_.path(pl.at->file);
      nlohmann::json loc;
      loc["artifactLocation"] = {{"uri", path_to_uri(path)}, {"index", add_artifact(path)}};
      const Span mark = pl.mark ? *pl.mark : *pl.at;
      const LineCol b = sm_.line_col(pl.at->file, pl.at->begin);
      const LineCol e = sm_.line_col(mark.file, std::max(mark.end, mark.begin));
      // SARIF requires the region to end at or after its start; the reported position and
      // the mark can differ (the example reports a statement but marks a name after it), so
      // the region spans from the reported position to the end of the mark.
      LineCol end = e;
      if (mark.file != pl.at->file || std::tie(e.line, e.column) < std::tie(b.line, b.column))
        end = b;
      loc["region"] = {{"startLine", b.line},
                       {"startColumn", b.column},
                       {"endLine", end.line},
                       {"endColumn", end.column}};
      return loc;
    }
    if (!pl.hint.empty())
      return nlohmann::json{
          {"artifactLocation", {{"uri", path_to_uri(pl.hint)}, {"index", add_artifact(pl.hint)}}}};
    return std::nullopt;
  }

  // Notes (and notes of notes) become relatedLocations carrying the note text.
  void collect_notes(const Diagnostic& d, const Place& pl, nlohmann::json& related) {
    for (const Diagnostic& n : d.notes) {
      const Place np = place_of_note(sm_, n, pl);
      nlohmann::json loc;
      loc["id"] = related.size();
      if (auto phys = physical(np)) loc["physicalLocation"] = *phys;
      loc["message"] = {{"text", escape_for_display(n.message)}};
      related.push_back(std::move(loc));
      collect_notes(n, np, related);
    }
  }

  const SourceManager& sm_;
  std::vector<std::string> artifact_uris_;
  std::map<std::string, std::size_t> artifact_index_;
  std::vector<std::string> rule_ids_;
  std::map<std::string, std::size_t> rule_index_;
};

// ---------------------------------------------------------------------------------------
// Typo suggestions

// Words longer than this are not identifiers anyone mistyped; refusing them bounds the cost.
constexpr std::size_t kMaxSuggestLength = 64;

char fold(char c) {
  return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
}

// Optimal-string-alignment Damerau–Levenshtein distance (adjacent transpositions count as
// one edit) in O(|a|*|b|) time with three rolling rows.
template <bool FoldCase> std::size_t edit_distance(std::string_view a, std::string_view b) {
  auto eq = [](char x, char y) { return FoldCase ? fold(x) == fold(y) : x == y; };
  std::vector<std::size_t> prev2(b.size() + 1), prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j)
    prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = eq(a[i - 1], b[j - 1]) ? 0 : 1;
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost});
      if (i > 1 && j > 1 && eq(a[i - 1], b[j - 2]) && eq(a[i - 2], b[j - 1]))
        cur[j] = std::min(cur[j], prev2[j - 2] + 1);
    }
    std::swap(prev2, prev);
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

} // namespace

// -----------------------------------------------------------------------------------------

const DiagKind& diag_kind(DiagId id) {
  return kKinds[static_cast<std::size_t>(id)];
}

Diagnostic& DiagnosticEngine::add(Diagnostic d) {
  if (d.severity == Severity::error) {
    if (errors_ >= error_limit_) {
      // The first error past the limit is replaced by one final too_many_errors; it counts
      // as an error itself, so errors_ == limit + 1 afterwards marks "already reported".
      if (errors_ == error_limit_) {
        const DiagKind& k = diag_kind(DiagId::too_many_errors);
        diags_.push_back(Diagnostic{k.severity,
                                    k.code,
                                    fmt::format(fmt::runtime(k.format), error_limit_),
                                    std::nullopt,
                                    std::nullopt,
                                    {},
                                    {},
                                    false});
        ++errors_;
      }
      // Callers may still attach notes to what they reported; they land in a sink that is
      // cleared each time so it never grows.
      overflow_sink_ = Diagnostic{};
      return overflow_sink_;
    }
    ++errors_;
  } else if (d.severity == Severity::warning) {
    ++warnings_;
  }
  diags_.push_back(std::move(d));
  return diags_.back();
}

void DiagnosticEngine::stop_early() {
  // Any error added at the limit is turned into the too_many_errors diagnostic by add().
  if (errors_ == error_limit_) add(Diagnostic{});
}

void DiagnosticEngine::sort() {
  // Located diagnostics first (by file, then offset), then file-level ones in report order,
  // and too-many-errors last of all since it announces that the list was cut short.
  auto key = [](const Diagnostic& d) {
    const std::optional<Span> at = location_of(d);
    const int rank = d.code == diag_kind(DiagId::too_many_errors).code ? 2 : at ? 0 : 1;
    return std::make_tuple(rank, at ? at->file : 0u, at ? at->begin : 0u);
  };
  std::stable_sort(diags_.begin(), diags_.end(),
                   [&](const Diagnostic& a, const Diagnostic& b) { return key(a) < key(b); });
}

std::string render_text(const DiagnosticEngine& engine, bool color) {
  const SourceManager& sm = engine.sources();
  const Palette pal = make_palette(color);
  std::string out;
  for (const Diagnostic& d : engine.all()) {
    const Place pl = place_of(sm, d);
    render_tree(out, sm, d, pl, pl.at.has_value(), pal);
  }
  return out;
}

std::string render_json(const DiagnosticEngine& engine) {
  const SourceManager& sm = engine.sources();
  nlohmann::json arr = nlohmann::json::array();
  for (const Diagnostic& d : engine.all())
    arr.push_back(json_of(sm, d, place_of(sm, d)));
  return dump(arr);
}

std::string render_sarif(const DiagnosticEngine& engine, const std::string& tool_version) {
  SarifBuilder b(engine.sources());
  nlohmann::json results = nlohmann::json::array();
  for (const Diagnostic& d : engine.all())
    results.push_back(b.result(d));

  nlohmann::json driver = {{"name", "thermnet"}};
  if (!tool_version.empty()) driver["version"] = tool_version;
  driver["rules"] = b.rules();

  nlohmann::json run;
  run["tool"] = {{"driver", std::move(driver)}};
  // Our columns count code points; say so, since consumers otherwise may assume UTF-16.
  run["columnKind"] = "unicodeCodePoints";
  run["artifacts"] = b.artifacts();
  run["results"] = std::move(results);

  nlohmann::json log;
  log["$schema"] = "https://json.schemastore.org/sarif-2.1.0.json";
  log["version"] = "2.1.0";
  log["runs"] = nlohmann::json::array({std::move(run)});
  return dump(log);
}

std::optional<std::string> closest_match(const std::string& word,
                                         const std::vector<std::string>& candidates) {
  if (word.empty() || word.size() > kMaxSuggestLength) return std::nullopt;
  const std::size_t limit = std::max<std::size_t>(1, word.size() / 3);
  // On equal distance, prefer the candidate whose differing characters are nearest in value, so
  // 'lens3' suggests 'lens2' rather than 'lens1' (the usual slip is to the neighbouring number).
  auto closeness = [&](const std::string& c) {
    std::size_t sum = 0;
    for (std::size_t i = 0; i < std::min(c.size(), word.size()); ++i)
      sum += static_cast<std::size_t>(std::abs(int(c[i]) - int(word[i])));
    return sum;
  };
  const std::string* best = nullptr;
  std::size_t best_dist = 0;
  std::size_t best_folded = 0;
  std::size_t best_close = 0;
  for (const std::string& c : candidates) {
    // The distance is at least the length difference; skipping hopeless candidates early
    // also bounds every computed matrix to (64 + 21)^2 cells.
    const std::size_t diff =
        c.size() > word.size() ? c.size() - word.size() : word.size() - c.size();
    if (diff > limit) continue;
    const std::size_t dist = edit_distance<false>(word, c);
    if (dist > limit || dist >= word.size()) continue;
    if (best != nullptr && dist > best_dist) continue;
    const std::size_t folded = edit_distance<true>(word, c);
    const std::size_t close = closeness(c);
    if (best == nullptr || dist < best_dist || folded < best_folded ||
        (folded == best_folded && close < best_close)) {
      best = &c;
      best_dist = dist;
      best_folded = folded;
      best_close = close;
    }
  }
  if (best == nullptr) return std::nullopt;
  return *best;
}

} // namespace thermnet::lang
