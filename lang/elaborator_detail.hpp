#pragma once
/// Helpers the elaborator's source files share (included only by them).

#include "lang/ast.hpp"
#include "lang/elaborator.hpp"
#include "lang/schema.hpp"
#include "lang/source.hpp"
#include "lang/units.hpp"

#include <fmt/format.h>

#include <initializer_list>
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

/// A key of a built-in statement: name, dimension, lower bound 0 (exclusive or not), doc.
KeySchema builtin_key(std::string name, Dimension d, bool min_exclusive, std::string doc);

/// A temperature key: bare numbers in degC, above absolute zero.
KeySchema temperature_key(std::string name, std::string doc);

/// Numbers for a message that compares them (a value and its range's bounds): {:g} each, unless
/// that makes two different ones look equal (1.0000001 outside 0 .. 1 is not "1"); then all with
/// the digits that read back exactly. `unit` follows each (" degC", or empty).
std::vector<std::string> compared_numbers(std::initializer_list<double> values,
                                          std::string_view unit = {});

/// Adds to `into` the params of `reads` it does not hold yet.
void add_reads(ParamReads& into, const ParamReads& reads);

/// True when a case setting's name is one of the case's own keys.
inline bool is_case_key(std::string_view k) {
  return k == "duration" || k == "initial" || k == "output";
}

} // namespace thermnet::lang::detail

namespace thermnet::lang {

/// While it lives, every param read (directly or through a value) is noted in `into` too.
class Elaborator::Reading {
public:
  /// Starts noting the reads of `e` into `into` (when `e` records reads).
  Reading(Elaborator& e, ParamReads& into) : e_(e), on_(e.recording_) {
    if (on_) e_.readers_.push_back(&into);
  }
  /// Ends the reading.
  ~Reading() { stop(); }
  /// Not copied.
  Reading(const Reading&) = delete;
  /// Not copied.
  Reading& operator=(const Reading&) = delete;
  /// Ends the reading before the end of its scope.
  void stop() {
    if (on_) e_.readers_.pop_back();
    on_ = false;
  }

private:
  Elaborator& e_;
  bool on_;
};

} // namespace thermnet::lang
