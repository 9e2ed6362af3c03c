#include "lang/parser.hpp"

#include "lang/grammar.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

namespace thermnet::lang {
namespace {

using grammar::is_ident_char;
using grammar::is_ident_start;
using grammar::It;
using grammar::Place;

/// Length of the UTF-8 sequence starting at p that is valid, or 0 if invalid.
std::size_t utf8_length(It p, It end) {
  auto c = static_cast<unsigned char>(*p);
  std::size_t n = c < 0x80           ? 1
                  : (c >> 5) == 0x6  ? 2
                  : (c >> 4) == 0xE  ? 3
                  : (c >> 3) == 0x1E ? 4
                                     : 0;
  if (n == 0 || static_cast<std::size_t>(end - p) < n) return 0;
  for (std::size_t i = 1; i < n; ++i)
    if ((static_cast<unsigned char>(p[i]) & 0xC0) != 0x80) return 0;
  if (n == 2 && c < 0xC2) return 0; // overlong
  return n;
}

/// What a block holds, which decides the messages and the recovery after a syntax error.
enum class Block { top, loop, submodel, case_items };

/// Drives the grammar statement by statement so one syntax error never hides the next one.
class Driver {
public:
  Driver(FileId id, const SourceManager& sources, DiagnosticEngine& diags)
      : id_(id), diags_(diags), original_(sources.text(id)), base_(original_.data()),
        end_(base_ + original_.size()) {}

  ast::File run() {
    file_.file_id = id_;
    const std::size_t errors_before = diags_.error_count();
    if (!prescan()) {
      file_.syntax_errors = diags_.error_count() - errors_before;
      return std::move(file_);
    }
    if (!copy_.empty()) { // the prescan blanked something: parse the copy
      base_ = copy_.data();
      end_ = base_ + copy_.size();
    }
    grammar_.emplace(base_, end_, original_, file_);
    // A statement takes a line (of 16 bytes or more in a real model): one allocation for them
    // all in a generated file of one per line.
    const auto size = static_cast<std::size_t>(end_ - base_);
    file_.statements.reserve(
        std::min(static_cast<std::size_t>(std::count(base_, end_, '\n')) + 1, size / 16 + 1));
    It p = base_;
    if (end_ - base_ >= 3 && std::equal(base_, base_ + 3, "\xEF\xBB\xBF")) p += 3; // a UTF-8 BOM
    parse_statements(p, file_.statements, Block::top, nullptr);
    if (p != end_ && diags_.saturated()) diags_.stop_early();
    // The expression array grew by doubling and lives as long as the model: up to half of it is
    // room never used, which the declarations and networks allocated next would sit above.
    file_.exprs.shrink_to_fit();
    file_.syntax_errors = diags_.error_count() - errors_before;
    return std::move(file_);
  }

private:
  std::uint32_t off(It p) const { return static_cast<std::uint32_t>(p - base_); }
  Span span(It a, It b) const { return Span{id_, off(a), off(b)}; }

  bool at_keyword(It p, const char* word) const {
    std::size_t n = std::char_traits<char>::length(word);
    return static_cast<std::size_t>(end_ - p) >= n && std::equal(word, word + n, p) &&
           (p + n == end_ || !is_ident_char(p[n]));
  }

  /// Calls f(p) for each bracket ( ) [ ] { } in code (not in a string or a comment); stops and
  /// returns false on a NUL byte or invalid UTF-8 (reported), or when f returns false.
  template <typename F> bool scan_brackets(F&& f) {
    // ASCII bytes that neither change the lexical state nor are brackets are stepped over at once
    // (most of a netlist).
    static constexpr auto plain = [] {
      std::array<bool, 256> t{};
      for (int c = 1; c < 0x80; ++c)
        t[static_cast<std::size_t>(c)] = true;
      for (const char c : std::string_view("\n\"#\\()[]{}"))
        t[static_cast<unsigned char>(c)] = false;
      return t;
    }();
    bool in_comment = false, in_string = false, escaped = false;
    for (It p = base_; p < end_;) {
      char c = *p;
      if (plain[static_cast<unsigned char>(c)]) {
        escaped = false;
        ++p;
        continue;
      }
      if (c == '\0') {
        diags_.report(DiagId::nul_byte, span(p, p + 1), std::nullopt);
        return false;
      }
      std::size_t n = utf8_length(p, end_);
      if (n == 0) {
        diags_.report(DiagId::not_utf8, span(p, p + 1), std::nullopt);
        return false;
      }
      const bool code = !in_comment && !in_string;
      if (c == '\n')
        in_comment = in_string = escaped = false;
      else if (in_comment) {
      } else if (in_string) {
        if (escaped)
          escaped = false;
        else if (c == '\\')
          escaped = true;
        else if (c == '"')
          in_string = false;
      } else if (c == '#') {
        in_comment = true;
      } else if (c == '"')
        in_string = true;
      const bool bracket = c == '(' || c == ')' || c == '[' || c == ']' || c == '{' || c == '}';
      if (code && bracket && !f(p)) return false;
      p += n;
    }
    return true;
  }

  /// Rejects input that is not text or nests too deeply, reports unclosed blocks, and blanks
  /// newlines and comments inside matched ( ) and [ ] (where a newline does not end a
  /// statement). A bracket that is never closed blanks nothing, so the error stays on its line.
  bool prescan() {
    // Pass 1: match brackets by kind; a closer pops its nearest opener of the same kind.
    std::vector<std::pair<It, char>> stack;
    std::vector<std::pair<It, It>> spans; // matched ( ) and [ ]
    std::vector<It> unclosed;             // unmatched '{'
    auto closer_of = [](char c) { return c == '(' ? ')' : c == '[' ? ']' : '}'; };
    bool ok = scan_brackets([&](It p) {
      char c = *p;
      if (c == '(' || c == '[' || c == '{') {
        if (static_cast<int>(stack.size()) >= max_nesting) {
          diags_.report(DiagId::too_deep, span(p, p + 1), std::nullopt, max_nesting);
          return false;
        }
        stack.emplace_back(p, c);
      } else if (c == ')' || c == ']' || c == '}') {
        for (std::size_t i = stack.size(); i-- > 0;)
          if (closer_of(stack[i].second) == c) {
            for (std::size_t k = i + 1; k < stack.size(); ++k)
              if (stack[k].second == '{') unclosed.push_back(stack[k].first);
            if (c != '}') spans.emplace_back(stack[i].first, p);
            stack.resize(i);
            break;
          }
      }
      return true;
    });
    if (!ok) return false;
    for (const auto& [p, c] : stack)
      if (c == '{') unclosed.push_back(p);
    std::sort(unclosed.begin(), unclosed.end());
    for (It b : unclosed)
      diags_.report(DiagId::unterminated_block, span(b, b + 1), std::nullopt, block_kind(b));
    unclosed_braces_ = !unclosed.empty();
    if (spans.empty()) return true;
    // Pass 2: blank newlines and comments inside the outermost matched brackets.
    std::sort(spans.begin(), spans.end());
    std::vector<std::pair<It, It>> outer;
    for (const auto& sp : spans)
      if (outer.empty() || sp.first > outer.back().second) outer.push_back(sp);
    // A bracket opens in code (not in a string or comment), so each span is read from there.
    for (const auto& [open, close] : outer) {
      bool in_comment = false, in_string = false, escaped = false;
      for (It p = open + 1; p < close; ++p) {
        const char c = *p;
        if (c == '\n') {
          in_comment = in_string = escaped = false;
          blank(p, 1);
        } else if (in_comment) {
          blank(p, 1);
        } else if (in_string) {
          if (escaped)
            escaped = false;
          else if (c == '\\')
            escaped = true;
          else if (c == '"')
            in_string = false;
        } else if (c == '#') {
          in_comment = true;
          blank(p, 1);
        } else if (c == '"') {
          in_string = true;
        }
      }
    }
    return true;
  }

  /// The first two words of a statement that failed to parse.
  ast::Unparsed salvage(It start) const {
    ast::Unparsed u;
    u.begin = off(start);
    u.end = off(start);
    auto word = [&](It& p, ast::Identifier& id) {
      p = skip_line_space(p);
      if (p == end_ || !is_ident_start(*p)) return false;
      It q = p;
      while (q < end_ && is_ident_char(*q))
        ++q;
      id.name = original_.substr(off(p), static_cast<std::size_t>(q - p));
      id.begin = off(p);
      id.end = off(q);
      p = q;
      return true;
    };
    It p = start;
    if (word(p, u.head)) word(p, u.name);
    return u;
  }

  /// What a '{' opens, for messages: "case", "series" or "parallel", else "block".
  std::string block_kind(It brace) const {
    It line = brace;
    while (line > base_ && line[-1] != '\n')
      --line;
    line = skip_line_space(line);
    for (const char* w : {"case", "series", "parallel", "submodel"})
      if (at_keyword(line, w)) return w;
    if (at_keyword(line, "for")) return "for loop";
    return "block";
  }

  /// Skips blanks, comments and continuations, but not newlines.
  It skip_line_space(It p) const {
    while (p < end_) {
      if (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\v' || *p == '\f')
        ++p;
      else if (*p == '#') {
        while (p < end_ && *p != '\n')
          ++p;
      } else if (*p == '\\') {
        It q = p + 1;
        while (q < end_ && (*q == ' ' || *q == '\t' || *q == '\r'))
          ++q;
        if (q < end_ && *q == '\n')
          p = q + 1;
        else
          break;
      } else
        break;
    }
    return p;
  }

  /// Skips everything that separates statements: blanks, comments, newlines and ';'.
  It skip_separators(It p) const {
    for (;;) {
      p = skip_line_space(p);
      if (p < end_ && (*p == '\n' || *p == ';'))
        ++p;
      else
        return p;
    }
  }

  /// The extent of the token starting at p (a word, a number, or one character).
  It token_end(It p) const {
    if (p >= end_ || *p == '\n' || *p == '\r') return p;
    It q = p;
    if (is_ident_char(*q) || *q == '.') {
      while (q < end_ && (is_ident_char(*q) || *q == '.'))
        ++q;
      return q;
    }
    std::size_t n = utf8_length(q, end_);
    return q + (n ? n : 1);
  }

  std::string describe_token(It p) const {
    if (p >= end_) return "end of file";
    if (*p == '\n' || *p == '\r') return "end of line";
    It q = token_end(p);
    std::string tok(p, q);
    if (tok.size() > 40) tok = tok.substr(0, 40) + "...";
    return "'" + tok + "'";
  }

  /// Moves past the statement that starts at `start`, matching braces; stops before a
  /// block's closing '}' when inside a block.
  It recover(It start, bool in_block) const {
    int braces = 0;
    bool in_string = false;
    for (It p = start; p < end_; ++p) {
      char c = *p;
      if (in_string) {
        if (c == '\\' && p + 1 < end_ && p[1] != '\n')
          ++p;
        else if (c == '"' || c == '\n')
          in_string = false;
        if (c != '\n') continue;
      }
      if (c == '"')
        in_string = true;
      else if (c == '#') {
        while (p + 1 < end_ && p[1] != '\n')
          ++p;
      } else if (c == '{')
        ++braces;
      else if (c == '}') {
        if (braces == 0 && in_block) return p;
        if (braces > 0 && --braces == 0 && !in_block) return p + 1;
      } else if ((c == '\n' || c == ';') && braces == 0) {
        return p;
      }
    }
    return end_;
  }

  /// Reports "expected WHAT, found TOKEN" at the first token at or after `where`.
  void report_expected(It where, const std::string& what) {
    where = skip_line_space(where);
    It tok_end = token_end(where);
    Diagnostic& d = diags_.report(DiagId::syntax_expected, span(where, where), span(where, tok_end),
                                  what + ", found " + describe_token(where));
    add_token_hint(d, where);
  }

  /// A hint for a token that starts like a number but is not one ("3mm", "1.2.3"), if it is one.
  std::optional<std::string> number_hint(It b, It e) const {
    if (b == e || !(std::isdigit(static_cast<unsigned char>(*b)) ||
                    (*b == '.' && e - b > 1 && std::isdigit(static_cast<unsigned char>(b[1])))))
      return std::nullopt;
    std::string tok(b, e);
    if (tok.size() > 40) return std::nullopt;
    char* stop = nullptr;
    std::strtod(tok.c_str(), &stop);
    std::string rest(stop);
    if (rest.empty()) return std::nullopt;
    std::string number = tok.substr(0, tok.size() - rest.size());
    if (std::isalpha(static_cast<unsigned char>(rest[0])) && !number.empty())
      return fmt::format("a unit goes in square brackets after the number: '{} [{}]'", number,
                         rest);
    return fmt::format("'{}' is not a number", tok);
  }

  /// Reports an expectation failure of the grammar; `which` names what the rule expected.
  void report_failure(It where, const std::string& which) {
    if (which == "'\"'" && (where == end_ || *where == '\n' || *where == '\r')) {
      // The closing quote of a string is missing: point at the opening one.
      It line = where;
      while (line > base_ && line[-1] != '\n')
        --line;
      It open = nullptr;
      bool in_string = false;
      for (It q = line; q < where; ++q) {
        if (in_string && *q == '\\')
          ++q;
        else if (*q == '"') {
          in_string = !in_string;
          if (in_string) open = q;
        } else if (!in_string && *q == '#')
          break;
      }
      if (open) {
        It stop = where;
        while (stop > open + 1 && (stop[-1] == '\r' || stop[-1] == ' '))
          --stop;
        diags_.report(DiagId::unterminated_string, span(open, open), span(open, stop));
        return;
      }
    }
    report_expected(where, which);
  }

  /// What a failed statement of a block should have been, for "expected ...".
  static const char* expected_in(Block b) {
    switch (b) {
    case Block::top:
      return "a statement (model, include, const, param, node, boundary, case, series, parallel, "
             "for, submodel or an element)";
    case Block::loop:
      return "a statement of a loop (node, boundary, series, parallel, for or an element)";
    case Block::submodel:
      return "a statement of a submodel (const, param, node, boundary, series, parallel, for or "
             "an element)";
    case Block::case_items:
      return "a case setting ('duration = ...', 'NAME.key = ...' or 'data \"file.csv\"')";
    }
    return "a statement";
  }

  /// Parses one statement or case item with `rule` (a callable taking the position); on failure
  /// reports and skips the statement.
  template <typename Rule, typename Attr>
  bool parse_one(It& p, Rule&& rule, Attr& attr, Block block) {
    const bool in_block = block != Block::top;
    It start = p;
    try {
      if (!rule(p)) {
        report_expected(start, expected_in(block));
        p = recover(start, in_block);
        return false;
      }
    } catch (const grammar::Expected& e) {
      report_failure(e.where, e.what);
      p = recover(start, in_block);
      return false;
    }
    p = grammar_->skip(p);
    tag_statement(attr, start, p);
    It q = skip_line_space(p);
    if (q == end_ || *q == '\n' || *q == ';' || (in_block && *q == '}')) {
      p = q;
      return true;
    }
    Diagnostic& d =
        diags_.report(DiagId::syntax_unexpected, span(q, q), span(q, token_end(q)),
                      describe_token(q) + "; expected the end of the statement (a newline or ';')");
    add_token_hint(d, q);
    // Like any statement with a syntax error, it is skipped: checking the part that parsed
    // would only add errors that the syntax error explains.
    p = recover(q, in_block);
    return false;
  }

  /// Explains a token that no rule can start: a non-ASCII character or a number glued to letters.
  void add_token_hint(Diagnostic& d, It q) const {
    if (q < end_ && static_cast<unsigned char>(*q) >= 0x80)
      d.notes.push_back(DiagnosticEngine::note(
          DiagId::note_text, std::nullopt,
          "names may use only ASCII letters, digits and '_'; other text belongs in a "
          "\"description\" or a # comment"));
    else if (auto hint = number_hint(q, token_end(q)))
      d.notes.push_back(DiagnosticEngine::note(DiagId::note_text, std::nullopt, *hint));
  }

  /// Gives a whole statement the byte range the driver parsed it from.
  template <typename Variant> void tag_statement(Variant& v, It begin, It end) {
    std::visit(
        [&](auto& node) {
          ast::Tagged& tag = ast::unboxed(node);
          tag.begin = off(begin);
          tag.end = off(end);
        },
        v);
  }

  /// Parses a block header with `rule`; on a syntax error reports it, skips the whole block and
  /// records the statement as unparsed.
  template <typename Rule> bool parse_header(It& p, Rule&& rule, Block block) {
    It start = p;
    try {
      if (rule(p)) return true;
      report_expected(start, "'case NAME {'");
    } catch (const grammar::Expected& e) {
      report_failure(e.where, e.what);
    }
    p = recover(start, block != Block::top);
    file_.unparsed.push_back(salvage(start));
    return false;
  }

  /// Reaching the end of the file inside a block: the prescan has reported an unclosed '{', else
  /// the block is reported here.
  void end_in_block(It open, const char* kind) {
    if (!unclosed_braces_)
      diags_.report(DiagId::unterminated_block, span(open, open), std::nullopt, kind);
  }

  /// Parses statements up to the end of the file (at the top) or the '}' closing the block that
  /// `open` starts (consumed).
  template <typename Body> void parse_statements(It& p, Body& out, Block block, It open) {
    const Place place = block == Block::top    ? Place::top
                        : block == Block::loop ? Place::loop
                                               : Place::submodel;
    for (;;) {
      p = skip_separators(p);
      if (p == end_) {
        if (open) end_in_block(open, block == Block::loop ? "for loop" : "submodel");
        return;
      }
      if (diags_.saturated()) return;
      if (*p == '}') {
        ++p;
        if (open) return;
        diags_.report(DiagId::syntax_unexpected, span(p - 1, p), std::nullopt, "'}'");
        continue;
      }
      if (at_keyword(p, "case")) {
        parse_case(p, out, block);
        continue;
      }
      if (at_keyword(p, "for") && parse_for(p, out, block)) continue;
      if (at_keyword(p, "submodel") && parse_submodel(p, out, block)) continue;
      ast::Statement s;
      It start = p;
      if (parse_one(
              p, [&](It& q) { return grammar_->statement(q, s, place); }, s, block))
        out.push_back(std::move(s));
      else
        file_.unparsed.push_back(salvage(start));
    }
  }

  /// A `for` block, unless the text is not a loop header (then false, nothing consumed).
  template <typename Body> bool parse_for(It& p, Body& out, Block block) {
    It start = p;
    ast::ForStmt f;
    try {
      if (!grammar_->loop_header(p, f.ranges)) return false;
    } catch (const grammar::Expected& e) {
      report_failure(e.where, e.what);
      p = recover(start, block != Block::top);
      file_.unparsed.push_back(salvage(start));
      return true;
    }
    parse_statements(p, f.body, Block::loop, start);
    f.begin = off(start);
    f.end = off(p);
    out.push_back(std::move(f));
    return true;
  }

  /// A `submodel` block, unless the text is not a submodel header (then false).
  template <typename Body> bool parse_submodel(It& p, Body& out, Block block) {
    It start = p;
    ast::SubmodelStmt m;
    try {
      if (!grammar_->submodel_header(p, m)) return false;
    } catch (const grammar::Expected& e) {
      report_failure(e.where, e.what);
      p = recover(start, block != Block::top);
      file_.unparsed.push_back(salvage(start));
      return true;
    }
    parse_statements(p, m.body, Block::submodel, start);
    m.begin = off(start);
    m.end = off(p);
    out.push_back(std::move(m));
    return true;
  }

  template <typename Body> void parse_case(It& p, Body& out, Block block) {
    It start = p;
    ast::CaseStmt cs;
    if (!parse_header(
            p, [&](It& q) { return grammar_->case_header(q, cs.name); }, block))
      return;
    if (!parse_case_items(p, cs.items, start, "case", &cs)) return;
    cs.begin = off(start);
    cs.end = off(p);
    out.push_back(std::move(cs));
  }

  /// Parses case settings up to the '}' that closes the block `open` starts; false when the
  /// error limit was reached.
  bool parse_case_items(It& p, std::vector<ast::CaseItem>& items, It open, const char* kind,
                        ast::CaseStmt* of) {
    for (;;) {
      p = skip_separators(p);
      if (p == end_) {
        end_in_block(open, kind);
        return true;
      }
      if (diags_.saturated()) return false;
      if (*p == '}') {
        ++p;
        return true;
      }
      if (at_keyword(p, "for")) {
        It start = p;
        ast::CaseFor f;
        bool header = false;
        try {
          header = grammar_->loop_header(p, f.ranges);
        } catch (const grammar::Expected& e) {
          report_failure(e.where, e.what);
          p = recover(start, true);
          continue;
        }
        if (header) {
          if (!parse_case_items(p, f.items, start, "for loop", of)) return false;
          f.begin = off(start);
          f.end = off(p);
          items.emplace_back(std::move(f));
          continue;
        }
      }
      ast::CaseItem item;
      const It start = p;
      if (parse_one(
              p, [&](It& q) { return grammar_->case_item(q, item); }, item, Block::case_items))
        items.push_back(std::move(item));
      else if (of && at_keyword(start, "data"))
        of->unparsed_data = true;
      else if (of && at_keyword(start, "duration"))
        of->unparsed_duration = true;
    }
  }

  /// Replaces n bytes at p (a position in the original text) by spaces in the parse copy, made
  /// on the first call (a file with nothing to blank is parsed in place).
  void blank(It p, std::size_t n) {
    if (copy_.empty()) copy_.assign(original_);
    for (std::size_t i = 0; i < n; ++i)
      copy_[static_cast<std::size_t>(p - original_.data()) + i] = ' ';
  }

  FileId id_;
  DiagnosticEngine& diags_;
  std::string_view original_; // names view the text itself; the copy dies with the driver
  std::string copy_;          // the text with newlines in brackets blanked, if any were
  It base_;                   // the text parsed: the original, or the copy
  It end_;
  ast::File file_;
  std::optional<grammar::Grammar> grammar_; // made once the prescan has chosen the text
  bool unclosed_braces_ = false;
};

} // namespace

ast::File parse_file(FileId id, const SourceManager& sources, DiagnosticEngine& diags) {
  return Driver(id, sources, diags).run();
}

} // namespace thermnet::lang
