#pragma once
/// The grammar of the netlist language, written with Boost.Spirit X3 (lang/grammar_x3.hpp); used
/// only by parser.cpp, which drives it statement by statement.
///
/// Each entry point either matches and advances the position, or does not match and leaves it
/// where it was; past a point where the rest is certain (after a keyword, after `key`), a missing
/// part throws Expected with what the messages call it ("'='", "value", "operand"). Newlines end
/// statements, so the rules skip blanks, comments and `\` continuations but not newlines; the
/// driver hands the grammar a copy of the text in which newlines and comments inside matched
/// ( ) and [ ] are blanked (offsets unchanged).

#include "lang/ast.hpp"
#include "lang/grammar_x3_builder.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace thermnet::lang::grammar {

using It = const char*;

/// An expectation that failed: where the expected part should have started, and its name.
struct Expected {
  It where;         ///< position of the failure
  std::string what; ///< what was expected, as messages name it
};

/// Where a statement stands; decides what may be left out (a submodel's param value).
enum class Place { top, loop, submodel };

/// True for a character that may start an identifier.
inline bool is_ident_start(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}
/// True for a character that may continue an identifier.
inline bool is_ident_char(char c) {
  return is_ident_start(c) || (c >= '0' && c <= '9');
}

/// The rules, reading the parse copy [base, end) and building nodes into `file`.
class Grammar {
public:
  /// A grammar over the parse copy; names view `original` (the same bytes at the same offsets).
  Grammar(It base, It end, std::string_view original, ast::File& file)
      : builder_{base, end, original, file} {}

  /// Skips blanks, '\r', comments and `\` continuations, not newlines.
  It skip(It p) const;
  /// True when `word` stands at p as a whole word (no skipping).
  bool at_word(It p, std::string_view word) const;

  /// A statement other than case, for and submodel blocks.
  bool statement(It& p, ast::Statement& out, Place place);
  /// `case NAME {` (the keyword is already known to be there).
  bool case_header(It& p, ast::Identifier& name);
  /// A case setting or data statement.
  bool case_item(It& p, ast::CaseItem& out);
  /// `for VAR in LO .. HI [, ...] {`; false (nothing consumed) when the text is not a loop header.
  bool loop_header(It& p, std::vector<ast::LoopRange>& ranges);
  /// `submodel NAME(TERMINAL, ...) {`; false (nothing consumed) when it is not a submodel header.
  bool submodel_header(It& p, ast::SubmodelStmt& out);
  /// An expression (exposed for the statement-level helpers and tests).
  bool expr(It& p, ast::Expr& out);

private:
  /// Runs an X3 rule from p; maps an expectation failure to Expected.
  template <typename Rule, typename Attr> bool run(It& p, const Rule& rule, Attr& attr);

  Builder builder_; // what the rules' semantic actions build into
};

} // namespace thermnet::lang::grammar
