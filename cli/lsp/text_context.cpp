#include "cli/lsp/text_context.hpp"

#include <algorithm>
#include <cctype>

namespace thermnet::cli::lsp {
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

} // namespace

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
  std::size_t p = stmt.size();
  while (p > 0 && (ident_char(stmt[p - 1]) || stmt[p - 1] == '.'))
    --p;
  std::string partial(stmt.substr(p));
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

} // namespace thermnet::cli::lsp
