#pragma once
/// The state the X3 rules' semantic actions build into (used only by the grammar): the file's
/// syntax tree, the text the names view, and the scratch lists that give every node its exact size.

#include "lang/ast.hpp"

#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace thermnet::lang::grammar {

/// One `^ [signs] operand` of a power chain, kept until the chain is complete.
struct PowerTail {
  int minus = 0;                  ///< number of '-' signs before the operand
  std::uint32_t signs_at = 0;     ///< where the signs (or the operand) start
  ast::Index operand = ast::none; ///< the operand
};

/// Builds nodes into an ast::File from what the rules match; reached from the semantic actions
/// through the X3 context (`x3::with<builder_tag>`).
struct Builder {
  /// A builder over the parse copy [base, end) whose names view `original`, adding to `file`.
  Builder(const char* base, const char* end, std::string_view original, ast::File& file)
      : base(base), end(end), original(original), file(file) {}

  const char* base;                     ///< first byte of the parse copy
  const char* end;                      ///< one past its last byte
  std::string_view original;            ///< the text names view (same bytes at the same offsets)
  ast::File& file;                      ///< where nodes go
  bool param_value_optional = false;    ///< a param may be left without value (in a submodel)
  std::vector<ast::KeyValue> keys;      ///< keys of the statement being parsed
  std::vector<ast::Ref> refs;           ///< terminals of the element being parsed
  std::vector<ast::InnerElement> parts; ///< inner elements of the series/parallel being parsed
  std::vector<PowerTail> tails;         ///< tails of the power chains being parsed (a stack)
  std::vector<ast::Index> args;         ///< arguments of the calls being parsed (a stack)

  /// Clears the scratch lists (after an expectation failure they may hold leftovers).
  void reset() {
    keys.clear();
    refs.clear();
    parts.clear();
    tails.clear();
    args.clear();
  }
  /// Byte offset of a position.
  std::uint32_t off(const char* p) const { return static_cast<std::uint32_t>(p - base); }
  /// A name matched at [a, b), viewing the original text.
  ast::Identifier identifier(const char* a, const char* b) const {
    ast::Identifier id;
    id.begin = off(a);
    id.end = off(b);
    id.name = original.substr(id.begin, id.end - id.begin);
    return id;
  }
  /// A string literal matched at [a, b) (quotes included): quotes removed, \" and \\ resolved.
  ast::String string_literal(const char* a, const char* b) const {
    ast::String s;
    s.begin = off(a);
    s.end = off(b);
    s.text.reserve(static_cast<std::size_t>(b - a) - 2);
    for (const char* c = a + 1; c + 1 < b; ++c) {
      if (*c == '\\') ++c; // the grammar lets only \\ and \" through
      s.text += *c;
    }
    return s;
  }
  /// Appends an expression node; its index.
  ast::Index add(const ast::ExprNode& n) {
    file.exprs.push_back(n);
    return static_cast<ast::Index>(file.exprs.size() - 1);
  }
  /// A node of operation `op` on a and b spanning [begin, end).
  ast::Index add(ast::ExprNode::Op op, ast::Index a, ast::Index b, std::uint32_t begin,
                 std::uint32_t end) {
    ast::ExprNode n;
    n.op = op;
    n.a = a;
    n.b = b;
    n.begin = begin;
    n.end = end;
    return add(n);
  }
  /// `a op b`, spanning both operands.
  ast::Index binary(ast::ExprNode::Op op, ast::Index a, ast::Index b) {
    return add(op, a, b, file.exprs[a].begin, file.exprs[b].end);
  }
  /// `-operand`, starting at `begin` (its signs).
  ast::Index negate(ast::Index operand, std::uint32_t begin) {
    return add(ast::ExprNode::Op::negate, operand, ast::none, begin, file.exprs[operand].end);
  }
  /// A number literal matched at [a, b). from_chars rounds correctly; a value beyond the range
  /// of double reads as infinity (or zero when tiny), which the evaluator reports.
  ast::Index number(const char* a, const char* b) {
    ast::ExprNode n;
    if (std::from_chars(a, b, n.value).ec == std::errc::result_out_of_range)
      n.value = std::strtod(std::string(a, b).c_str(), nullptr);
    n.begin = off(a);
    n.end = off(b);
    return add(n);
  }
  /// The expression whose root is `root`.
  ast::Expr expr(ast::Index root) const {
    ast::Expr e;
    e.root = root;
    e.begin = file.exprs[root].begin;
    e.end = file.exprs[root].end;
    return e;
  }
};

} // namespace thermnet::lang::grammar
