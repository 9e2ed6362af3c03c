#include "lang/ast.hpp"

namespace thermnet::lang::ast {

namespace {
const std::vector<IndexItem> no_index;
const std::vector<Ref> no_parts;
} // namespace

const std::vector<IndexItem>& Ref::index() const {
  return tail ? tail->index : no_index;
}

const std::vector<Ref>& Ref::rest() const {
  return tail ? tail->rest : no_parts;
}

Tagged Value::span() const {
  if (!ref) return expr;
  return *ref;
}

const Tagged& tag_of(const Statement& s) {
  return std::visit([](const auto& stmt) -> const Tagged& { return unboxed(stmt); }, s);
}

} // namespace thermnet::lang::ast
