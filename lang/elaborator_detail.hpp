#pragma once
/// Helpers the elaborator's source files share (included only by them).

#include "lang/ast.hpp"
#include "lang/source.hpp"

#include <fmt/format.h>

#include <string>
#include <string_view>
#include <vector>

namespace thermnet::lang::detail {

/// The identifier a value consists of, if it is a bare name.
inline const ast::Identifier* as_identifier(const ast::Value& v, const ast::File& file) {
  const ast::Expr* e = v.as_expr();
  if (!e) return nullptr;
  const ast::ExprNode& n = file.node(e->root);
  return n.op == ast::ExprNode::Op::name ? &file.names[n.a] : nullptr;
}

inline Span span_of(FileId f, const ast::Tagged& t) {
  return Span{f, t.begin, t.end};
}

inline std::string list_names(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size() && i < 4; ++i)
    out += (i ? ", '" : "'") + names[i] + "'";
  if (names.size() > 4) out += fmt::format(" and {} more", names.size() - 4);
  return out;
}

/// Sets a variable for the lifetime of the guard, then restores it.
template <typename T> class Restore {
public:
  Restore(T& var, T value) : var_(var), saved_(var) { var_ = value; }
  ~Restore() { var_ = saved_; }
  Restore(const Restore&) = delete;
  Restore& operator=(const Restore&) = delete;

private:
  T& var_;
  T saved_;
};

/// True when a case setting's name is one of the case's own keys.
inline bool is_case_key(std::string_view k) {
  return k == "duration" || k == "initial" || k == "output";
}

} // namespace thermnet::lang::detail
