#include "editors/lsp/text_context.hpp"

#include <algorithm>
#include <cctype>

namespace thermnet::lsp {
namespace {

bool ident_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

/// Splits a statement's text into tokens: identifiers/numbers, strings, `[unit]`, single
/// punctuation characters.
std::vector<std::string> tokenize(std::string_view s) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i < s.size()) {
    char c = s[i];
    if (std::isspace(static_cast<unsigned char>(c)) || c == '\\') {
      ++i;
    } else if (ident_char(c) || c == '.') {
      std::size_t j = i;
      while (j < s.size() && (ident_char(s[j]) || s[j] == '.'))
        ++j;
      out.emplace_back(s.substr(i, j - i));
      i = j;
    } else if (c == '"' || c == '[') {
      char close = c == '"' ? '"' : ']';
      std::size_t j = s.find(close, i + 1);
      j = j == std::string_view::npos ? s.size() : j + 1;
      out.emplace_back(s.substr(i, j - i));
      i = j;
    } else {
      out.emplace_back(1, c);
      ++i;
    }
  }
  return out;
}

/// The offset one past the `]` that closes the `[` at `open`, on the same line, or npos.
std::size_t closing_bracket(std::string_view text, std::size_t open) {
  int depth = 0;
  for (std::size_t i = open; i < text.size() && text[i] != '\n'; ++i) {
    if (text[i] == '[') ++depth;
    if (text[i] == ']' && --depth == 0) return i + 1;
  }
  return std::string_view::npos;
}

/// The offset of the `[` that opens the `]` at `close`, on the same line, or npos.
std::size_t opening_bracket(std::string_view text, std::size_t close) {
  int depth = 0;
  for (std::size_t i = close + 1; i-- > 0 && text[i] != '\n';) {
    if (text[i] == ']') ++depth;
    if (text[i] == '[' && --depth == 0) return i;
  }
  return std::string_view::npos;
}

} // namespace

std::string qualified_name(std::string_view text, const Word& w) {
  std::size_t b = w.begin;
  // Leftwards over `.`, an optional `[...]` and an identifier, as long as the path goes on
  // (`..` is a range, not a path).
  while (b > 1 && text[b - 1] == '.' && text[b - 2] != '.') {
    std::size_t p = b - 1;
    if (text[p - 1] == ']') {
      p = opening_bracket(text, p - 1);
      if (p == std::string_view::npos) break;
    }
    std::size_t s = p;
    while (s > 0 && ident_char(text[s - 1]))
      --s;
    if (s == p || std::isdigit(static_cast<unsigned char>(text[s]))) break;
    b = s;
  }
  std::size_t e = w.end;
  if (e < text.size() && text[e] == '[') {
    std::size_t close = closing_bracket(text, e);
    if (close != std::string_view::npos) e = close;
  }
  std::string out;
  for (char c : text.substr(b, e - b))
    if (!std::isspace(static_cast<unsigned char>(c))) out += c;
  return out;
}

std::optional<std::size_t> loop_variable(std::string_view text, const Word& w) {
  const std::size_t n = w.text.size();
  for (std::size_t pos = text.rfind(w.text, w.begin); pos != std::string_view::npos;
       pos = pos == 0 ? std::string_view::npos : text.rfind(w.text, pos - 1)) {
    if ((pos > 0 && ident_char(text[pos - 1])) ||
        (pos + n < text.size() && ident_char(text[pos + n])))
      continue;
    std::size_t i = pos + n;
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t'))
      ++i;
    if (i == pos + n || text.compare(i, 2, "in") != 0 ||
        (i + 2 < text.size() && ident_char(text[i + 2])))
      continue;
    // The header: from the statement's start (line, `{` or `;`) it reads `for ...`.
    std::size_t start = text.find_last_of("\n{;", pos);
    start = start == std::string_view::npos ? 0 : start + 1;
    while (start < pos && std::isspace(static_cast<unsigned char>(text[start])))
      ++start;
    if (text.compare(start, 3, "for") == 0 && start + 3 < text.size() &&
        std::isspace(static_cast<unsigned char>(text[start + 3])))
      return pos;
  }
  return std::nullopt;
}

std::optional<Word> word_at(std::string_view text, std::size_t at) {
  at = std::min(at, text.size());
  std::size_t b = at, e = at;
  while (b > 0 && ident_char(text[b - 1]))
    --b;
  while (e < text.size() && ident_char(text[e]))
    ++e;
  if (b == e) return std::nullopt;
  if (std::isdigit(static_cast<unsigned char>(text[b]))) return std::nullopt; // a number
  return Word{b, e, std::string(text.substr(b, e - b))};
}

bool followed_by_assignment(std::string_view text, const Word& w) {
  std::size_t i = w.end;
  while (i < text.size() && (text[i] == ' ' || text[i] == '\t'))
    ++i;
  return i < text.size() && text[i] == '=' && (i + 1 >= text.size() || text[i + 1] != '=');
}

bool StatementContext::value_position() const {
  if (tokens.empty()) return false;
  const std::string& last = tokens.back();
  return last == "=" || last == "(" || last == "," || last == "+" || last == "-" || last == "*" ||
         last == "/" || last == "^" || last == ":";
}

std::string StatementContext::current_key() const {
  for (std::size_t i = tokens.size(); i-- > 1;)
    if (tokens[i] == "=") return tokens[i - 1];
  return {};
}

std::size_t StatementContext::positional_count() const {
  for (std::size_t i = 0; i + 1 < tokens.size(); ++i)
    if (tokens[i + 1] == "=") return i;
  return tokens.size();
}

std::vector<std::string> StatementContext::given_keys() const {
  std::vector<std::string> out;
  for (std::size_t i = 0; i + 1 < tokens.size(); ++i)
    if (tokens[i + 1] == "=") out.push_back(tokens[i]);
  return out;
}

StatementContext context_at(std::string_view text, std::size_t at) {
  at = std::min(at, text.size());
  StatementContext ctx;
  // One pass from the start: block nesting, strings, comments and where the statement begins.
  std::vector<std::string> blocks;
  std::string line_first_word;
  bool at_line_start = true;
  bool in_string = false, in_comment = false;
  std::size_t stmt_begin = 0;
  bool inner = false;
  for (std::size_t i = 0; i < at; ++i) {
    char c = text[i];
    if (c == '\n') {
      in_comment = false;
      in_string = false;
      bool continued = i > 0 && text[i - 1] == '\\';
      if (!continued) {
        stmt_begin = i + 1;
        inner = false;
        at_line_start = true;
      }
      continue;
    }
    if (in_comment) continue;
    if (in_string) {
      if (c == '"') in_string = false;
      continue;
    }
    if (c == '#') {
      in_comment = true;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '{' || c == ';' || c == '}') {
      if (c == '{') blocks.push_back(line_first_word);
      if (c == '}' && !blocks.empty()) blocks.pop_back();
      stmt_begin = i + 1;
      inner = c != '}';
    } else if (at_line_start && ident_char(c)) {
      std::size_t j = i;
      while (j < text.size() && ident_char(text[j]))
        ++j;
      line_first_word = std::string(text.substr(i, j - i));
      at_line_start = false;
    } else if (at_line_start && !std::isspace(static_cast<unsigned char>(c))) {
      at_line_start = false;
    }
  }
  ctx.in_comment = in_comment;
  ctx.in_string = in_string;
  ctx.inner = inner && !blocks.empty();
  ctx.block = blocks.empty() ? "" : blocks.back();
  std::string_view stmt = text.substr(stmt_begin, at - stmt_begin);
  // The partial word (with an object before a dot) ends at the cursor.
  // The object may be a path with indices (`p[2, 2].`, `u1.pcb.`).
  std::size_t p = stmt.size();
  while (p > 0) {
    if (ident_char(stmt[p - 1]) || stmt[p - 1] == '.') {
      --p;
    } else if (stmt[p - 1] == ']' && p < stmt.size() && stmt[p] == '.') {
      std::size_t open = opening_bracket(stmt, p - 1);
      if (open == std::string_view::npos) break;
      p = open;
    } else {
      break;
    }
  }
  std::string partial;
  for (char c : stmt.substr(p))
    if (!std::isspace(static_cast<unsigned char>(c))) partial += c;
  if (auto dot = partial.rfind('.'); dot != std::string::npos) {
    ctx.object = partial.substr(0, dot);
    partial = partial.substr(dot + 1);
  }
  ctx.partial = partial;
  ctx.tokens = tokenize(stmt.substr(0, p));
  return ctx;
}

std::optional<CodeWord> code_word_at(std::string_view text, std::size_t at) {
  std::optional<Word> w = word_at(text, at);
  if (!w) return std::nullopt;
  StatementContext ctx = context_at(text, w->begin);
  if (ctx.in_comment || ctx.in_string) return std::nullopt;
  return CodeWord{std::move(*w), std::move(ctx)};
}

} // namespace thermnet::lsp
