#pragma once
/// The grammar of the netlist language as a recursive-descent parser (used only by parser.cpp).
///
/// Each rule either matches and advances the position, or does not match and leaves it where it
/// was; past a point where the rest is certain (after a keyword, after `key`), a missing part
/// throws Expected with what the messages call it ("'='", "value", "operand"). Newlines end
/// statements, so the rules skip blanks, comments and `\` continuations but not newlines; the
/// driver hands the grammar a copy of the text in which newlines and comments inside matched
/// ( ) and [ ] are blanked (offsets unchanged).

#include "lang/ast.hpp"

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
      : base_(base), end_(end), original_(original), file_(file) {}

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
  std::uint32_t off(It p) const { return static_cast<std::uint32_t>(p - base_); }
  std::string_view view(It a, It b) const { return original_.substr(off(a), off(b) - off(a)); }
  [[noreturn]] void fail(It where, const char* what) const;

  bool lit(It& p, char c) const;
  void expect(It& p, char c, const char* what) const;
  bool kw(It& p, std::string_view word) const;
  bool eol(It& p) const;
  bool identifier(It& p, ast::Identifier& out) const;
  void expect_identifier(It& p, ast::Identifier& out) const;
  bool string_literal(It& p, ast::String& out) const;
  bool unit(It& p, ast::UnitText& out) const;
  bool number(It& p, double& value, It& begin) const;

  ast::Index add(ast::ExprNode n);
  ast::Index negate(ast::Index operand, std::uint32_t begin);
  bool primary(It& p, ast::Index& out);
  bool power(It& p, ast::Index& out);
  bool signed_power(It& p, ast::Index& out);
  bool term(It& p, ast::Index& out);
  bool expression(It& p, ast::Index& out);
  void expect_expr(It& p, ast::Expr& out, const char* what);
  ast::Expr as_expr(ast::Index root) const;

  bool index_list(It& p, std::vector<ast::IndexItem>& out);
  bool ref(It& p, ast::Ref& out, bool target);
  bool decl_name(It& p, ast::Ref& out);
  bool terminal(It& p, ast::Ref& out);
  bool point_signal(It& p, ast::Value& out);
  bool table_signal(It& p, ast::Value& out);
  bool value(It& p, ast::Value& out);
  void expect_value(It& p, ast::Value& out);
  bool key_value(It& p, ast::KeyValue& out);
  void keys(It& p, std::vector<ast::KeyValue>& out);
  void doc(It& p, std::unique_ptr<ast::String>& out);
  bool loop_range(It& p, ast::LoopRange& out, bool committed);

  bool param(It& p, ast::ParamStmt& out, Place place);
  bool node(It& p, ast::NodeStmt& out);
  bool composite(It& p, ast::CompositeStmt& out);
  bool element(It& p, ast::ElementStmt& out);
  bool case_data(It& p, ast::CaseData& out);
  bool case_assign(It& p, ast::CaseAssign& out);

  It base_;
  It end_;
  std::string_view original_;
  ast::File& file_;
  std::vector<ast::KeyValue> key_scratch_; // keys of the statement being parsed
  std::vector<ast::Ref> ref_scratch_;      // terminals of the element being parsed
};

} // namespace thermnet::lang::grammar
