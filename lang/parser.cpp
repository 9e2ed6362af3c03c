#include "lang/parser.hpp"

#include "lang/grammar_def.hpp"

#include <string>
#include <vector>

namespace thermnet::lang {
namespace {

namespace x3 = boost::spirit::x3;
using It = const char*;

bool is_ident_start(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}
bool is_ident_char(char c) {
  return is_ident_start(c) || (c >= '0' && c <= '9');
}

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

/// Drives the X3 rules statement by statement so one syntax error never hides the next one.
class Driver {
public:
  Driver(FileId id, const SourceManager& sources, DiagnosticEngine& diags)
      : id_(id), diags_(diags), copy_(sources.text(id)), base_(copy_.data()),
        end_(base_ + copy_.size()) {}

  ast::File run() {
    ast::File file;
    file.file_id = id_;
    if (!prescan()) return file;
    It p = base_;
    for (;;) {
      p = skip_separators(p);
      if (p == end_ || diags_.saturated()) break;
      if (*p == '}') {
        diags_.report(DiagId::syntax_unexpected, span(p, p + 1), std::nullopt, "'}'");
        ++p;
        continue;
      }
      if (at_keyword(p, "case")) {
        parse_case(p, file);
        continue;
      }
      ast::Statement s;
      if (parse_one(p, grammar::statement, s, false)) file.statements.push_back(std::move(s));
    }
    return file;
  }

private:
  std::uint32_t off(It p) const { return static_cast<std::uint32_t>(p - base_); }
  Span span(It a, It b) const { return Span{id_, off(a), off(b)}; }

  bool at_keyword(It p, const char* word) const {
    std::size_t n = std::char_traits<char>::length(word);
    return static_cast<std::size_t>(end_ - p) >= n && std::equal(word, word + n, p) &&
           (p + n == end_ || !is_ident_char(p[n]));
  }

  /// Rejects input that is not text or nests too deeply, reports unclosed blocks, and blanks
  /// newlines and comments inside ( ) and [ ] (where a newline does not end a statement).
  bool prescan() {
    std::vector<It> braces;
    std::vector<char> open; // the kinds of the open brackets
    int depth = 0;
    bool in_comment = false, in_string = false;
    for (It p = base_; p < end_;) {
      char c = *p;
      if (c == '\0') {
        diags_.report(DiagId::nul_byte, span(p, p + 1), std::nullopt);
        return false;
      }
      std::size_t n = utf8_length(p, end_);
      if (n == 0) {
        diags_.report(DiagId::not_utf8, span(p, p + 1), std::nullopt);
        return false;
      }
      bool in_parens = !open.empty() && open.back() != '{';
      if (in_parens && (c == '\n' || in_comment)) blank(p, n);
      if (c == '\n')
        in_comment = in_string = false;
      else if (in_comment) {
      } else if (in_string) {
        if (c == '\\' && p + 1 < end_ && p[1] != '\n')
          n = 2;
        else if (c == '"')
          in_string = false;
      } else if (c == '#')
        in_comment = true;
      else if (c == '"')
        in_string = true;
      else if (c == '(' || c == '[' || c == '{') {
        if (++depth > max_nesting) {
          diags_.report(DiagId::too_deep, span(p, p + 1), std::nullopt, max_nesting);
          return false;
        }
        if (c == '{') braces.push_back(p);
      } else if (c == ')' || c == ']' || c == '}') {
        if (depth > 0) --depth;
        if (c == '}' && !braces.empty()) braces.pop_back();
      }
      p += n;
    }
    for (It b : braces)
      diags_.report(DiagId::unterminated_block, span(b, b + 1), std::nullopt, "block");
    unclosed_braces_ = !braces.empty();
    return true;
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

  void report_expected(It where, const std::string& what) {
    std::string msg = what + ", found " + describe_token(where);
    diags_.report(DiagId::syntax_expected, span(where, where), span(where, token_end(where)), msg);
  }

  /// Parses one statement or case item with `rule`; on failure reports and skips the statement.
  template <typename Rule, typename Attr>
  bool parse_one(It& p, Rule const& rule, Attr& attr, bool in_block) {
    It start = p;
    try {
      auto const parser = x3::with<grammar::buffer_tag>(base_)[rule];
      if (!x3::phrase_parse(p, end_, parser, grammar::line_skipper, attr)) {
        report_expected(start, in_block
                                   ? "expected a case setting ('duration = ...', 'NAME.key = ...' "
                                     "or 'data \"file.csv\"')"
                                   : "expected a statement (model, include, const, param, node, "
                                     "boundary, case, series, parallel or an element)");
        p = recover(start, in_block);
        return false;
      }
    } catch (x3::expectation_failure<It> const& e) {
      report_expected(e.where(), "expected " + e.which());
      p = recover(start, in_block);
      return false;
    }
    tag_statement(attr, start, p);
    It q = skip_line_space(p);
    if (q == end_ || *q == '\n' || *q == ';' || (in_block && *q == '}')) {
      p = q;
      return true;
    }
    diags_.report(DiagId::syntax_unexpected, span(q, q), span(q, token_end(q)),
                  describe_token(q) + "; expected the end of the statement (a newline or ';')");
    p = recover(q, in_block);
    return true;
  }

  /// Gives a whole statement the byte range the driver parsed it from.
  template <typename Variant> void tag_statement(Variant& v, It begin, It end) {
    boost::apply_visitor(
        [&](auto& node) {
          node.begin = off(begin);
          node.end = off(end);
        },
        v);
  }

  void parse_case(It& p, ast::File& file) {
    It start = p;
    ast::CaseStmt cs;
    if (!parse_header(p, cs.name)) return;
    for (;;) {
      p = skip_separators(p);
      if (p == end_) {
        // The prescan has already reported the unclosed '{'.
        if (!unclosed_braces_)
          diags_.report(DiagId::unterminated_block, span(start, start), std::nullopt, "case");
        break;
      }
      if (diags_.saturated()) return;
      if (*p == '}') {
        ++p;
        break;
      }
      ast::CaseItem item;
      if (parse_one(p, grammar::case_item, item, true)) cs.items.push_back(std::move(item));
    }
    cs.begin = off(start);
    cs.end = off(p);
    file.statements.emplace_back(std::move(cs));
  }

  bool parse_header(It& p, ast::Identifier& name) {
    It start = p;
    try {
      auto const parser = x3::with<grammar::buffer_tag>(base_)[grammar::case_header];
      if (x3::phrase_parse(p, end_, parser, grammar::line_skipper, name)) return true;
      report_expected(start, "expected 'case NAME {'");
    } catch (x3::expectation_failure<It> const& e) {
      report_expected(e.where(), "expected " + e.which());
    }
    p = recover(start, false);
    return false;
  }

  /// Replaces n bytes at p (inside the parse copy) by spaces.
  void blank(It p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i)
      copy_[static_cast<std::size_t>(p - base_) + i] = ' ';
  }

  FileId id_;
  DiagnosticEngine& diags_;
  std::string copy_;
  It base_;
  It end_;
  bool unclosed_braces_ = false;
};

} // namespace

ast::File parse_file(FileId id, const SourceManager& sources, DiagnosticEngine& diags) {
  return Driver(id, sources, diags).run();
}

} // namespace thermnet::lang
