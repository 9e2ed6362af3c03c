#include "lang/grammar.hpp"

#include <charconv>
#include <cstdlib>
#include <iterator>

namespace thermnet::lang::grammar {
namespace {

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

/// Moves a run of parsed items into a vector of exactly their number (one allocation).
template <typename T> std::vector<T> take(std::vector<T>& scratch, std::size_t from) {
  std::vector<T> out;
  out.reserve(scratch.size() - from);
  for (std::size_t i = from; i < scratch.size(); ++i)
    out.push_back(std::move(scratch[i]));
  scratch.resize(from);
  return out;
}

} // namespace

// --- lexical ----------------------------------------------------------------------------------

It Grammar::skip(It p) const {
  while (p < end_) {
    const char c = *p;
    if (c == ' ' || c == '\t' || c == '\r') {
      ++p;
    } else if (c == '#') {
      while (p < end_ && *p != '\n' && *p != '\r')
        ++p;
    } else if (c == '\\') {
      It q = p + 1;
      while (q < end_ && (*q == ' ' || *q == '\t'))
        ++q;
      if (q < end_ && *q == '\r') {
        p = q + 1 < end_ && q[1] == '\n' ? q + 2 : q + 1;
      } else if (q < end_ && *q == '\n') {
        p = q + 1;
      } else {
        break;
      }
    } else {
      break;
    }
  }
  return p;
}

bool Grammar::at_word(It p, std::string_view word) const {
  return static_cast<std::size_t>(end_ - p) >= word.size() &&
         std::string_view(p, word.size()) == word &&
         (p + word.size() == end_ || !is_ident_char(p[word.size()]));
}

void Grammar::fail(It where, const char* what) const {
  throw Expected{where, what};
}

bool Grammar::lit(It& p, char c) const {
  It q = skip(p);
  if (q == end_ || *q != c) return false;
  p = q + 1;
  return true;
}

void Grammar::expect(It& p, char c, const char* what) const {
  if (!lit(p, c)) fail(p, what);
}

bool Grammar::kw(It& p, std::string_view word) const {
  It q = skip(p);
  if (!at_word(q, word)) return false;
  p = q + word.size();
  return true;
}

bool Grammar::eol(It& p) const {
  It q = skip(p);
  if (q == end_ || *q != '\n') return false;
  p = q + 1;
  return true;
}

bool Grammar::identifier(It& p, ast::Identifier& out) const {
  It q = skip(p);
  if (q == end_ || !is_ident_start(*q)) return false;
  It r = q + 1;
  while (r < end_ && is_ident_char(*r))
    ++r;
  out.begin = off(q);
  out.end = off(r);
  out.name = view(q, r);
  p = r;
  return true;
}

void Grammar::expect_identifier(It& p, ast::Identifier& out) const {
  if (!identifier(p, out)) fail(p, "name");
}

bool Grammar::string_literal(It& p, ast::String& out) const {
  It q = skip(p);
  if (q == end_ || *q != '"') return false;
  std::string text;
  It r = q + 1;
  while (r < end_) {
    const char c = *r;
    if (c == '\\' && r + 1 < end_ && (r[1] == '\\' || r[1] == '"')) {
      text += r[1];
      r += 2;
      continue;
    }
    if (c == '"' || c == '\\' || c == '\n' || c == '\r') break;
    text += c;
    ++r;
  }
  if (r == end_ || *r != '"') fail(r, "'\"'");
  out.begin = off(q);
  out.end = off(r + 1);
  out.text = std::move(text);
  p = r + 1;
  return true;
}

bool Grammar::unit(It& p, ast::UnitText& out) const {
  It q = skip(p);
  if (q == end_ || *q != '[') return false;
  It r = skip(q + 1);
  It t = r;
  while (t < end_ && *t != ']' && *t != '[' && *t != '\n' && *t != '\r')
    ++t;
  out.begin = off(r);
  out.end = off(t);
  out.text.assign(r, t);
  p = t;
  expect(p, ']', "']'");
  return true;
}

// An unsigned real: digits with an optional fraction (a leading dot is allowed, a trailing one
// is not, and a '.' followed by another '.' is a range, not a decimal point) and an optional
// exponent; never glued to letters or to a further '.' (so `3mm` and `1.2.3` are not numbers).
bool Grammar::number(It& p, double& value, It& begin) const {
  It q = skip(p);
  It r = q;
  while (r < end_ && is_digit(*r))
    ++r;
  const bool integer = r > q;
  if (r < end_ && *r == '.' && !(r + 1 < end_ && r[1] == '.')) {
    It f = r + 1;
    while (f < end_ && is_digit(*f))
      ++f;
    if (f == r + 1) return false; // no fraction: neither "1." nor "." is a number
    r = f;
  } else if (!integer) {
    return false;
  }
  if (r < end_ && (*r == 'e' || *r == 'E')) {
    It e = r + 1;
    if (e < end_ && (*e == '+' || *e == '-')) ++e;
    It d = e;
    while (d < end_ && is_digit(*d))
      ++d;
    if (d > e) r = d; // "1e" or "1e+" without digits: the exponent is not part of the number
  }
  if (r < end_ && (is_ident_char(*r) || (*r == '.' && !(r + 1 < end_ && r[1] == '.'))))
    return false;
  const auto [stop, ec] = std::from_chars(q, r, value);
  if (ec == std::errc::result_out_of_range)
    value = std::strtod(std::string(q, r).c_str(), nullptr); // infinity, or zero when tiny
  else if (ec != std::errc() || stop != r)
    return false;
  begin = q;
  p = r;
  return true;
}

// --- expressions ------------------------------------------------------------------------------

ast::Index Grammar::add(ast::ExprNode n) {
  file_.exprs.push_back(n);
  return static_cast<ast::Index>(file_.exprs.size() - 1);
}

ast::Index Grammar::negate(ast::Index operand, std::uint32_t begin) {
  ast::ExprNode n;
  n.op = ast::ExprNode::Op::negate;
  n.a = operand;
  n.begin = begin;
  n.end = file_.exprs[operand].end;
  return add(n);
}

ast::Expr Grammar::as_expr(ast::Index root) const {
  ast::Expr e;
  e.root = root;
  e.begin = file_.exprs[root].begin;
  e.end = file_.exprs[root].end;
  return e;
}

bool Grammar::primary(It& p, ast::Index& out) {
  using Op = ast::ExprNode::Op;
  double v = 0;
  It start = p;
  It begin = nullptr;
  if (number(p, v, begin)) { // a quantity: a number with an optional unit
    ast::ExprNode n;
    n.value = v;
    n.begin = off(begin);
    n.end = off(p);
    ast::UnitText u;
    if (unit(p, u)) {
      n.op = Op::quantity;
      n.a = static_cast<ast::Index>(file_.units.size());
      n.end = off(p);
      file_.units.push_back(std::move(u));
    }
    out = add(n);
    return true;
  }
  ast::Identifier id;
  if (identifier(p, id)) {
    It after = p;
    if (lit(p, '(')) { // a call
      std::vector<ast::Index> args;
      ast::Index a = ast::none;
      if (expression(p, a)) {
        args.push_back(a);
        while (lit(p, ',')) {
          if (!expression(p, a)) fail(p, "expression");
          args.push_back(a);
        }
      }
      expect(p, ')', "')'");
      ast::ExprNode n;
      n.op = Op::call;
      n.a = static_cast<ast::Index>(file_.names.size());
      n.b = static_cast<ast::Index>(file_.args.size());
      n.count = static_cast<std::uint32_t>(args.size());
      n.begin = id.begin;
      n.end = off(p);
      file_.names.push_back(id);
      file_.args.insert(file_.args.end(), args.begin(), args.end());
      out = add(n);
      return true;
    }
    p = after;
    ast::ExprNode n;
    n.op = Op::name;
    n.a = static_cast<ast::Index>(file_.names.size());
    n.begin = id.begin;
    n.end = id.end;
    file_.names.push_back(id);
    out = add(n);
    return true;
  }
  It open = skip(p);
  if (lit(p, '(')) { // a parenthesised expression
    ast::Index inner = ast::none;
    if (!expression(p, inner)) {
      p = start;
      return false;
    }
    expect(p, ')', "')'");
    ast::ExprNode n;
    n.op = Op::group;
    n.a = inner;
    n.begin = off(open);
    n.end = off(p);
    out = add(n);
    return true;
  }
  p = start;
  return false;
}

// `base ^ [signs] e1 ^ [signs] e2 ...`, right-associative; every power node of the chain spans the
// whole chain (as messages about it mark it).
bool Grammar::power(It& p, ast::Index& out) {
  using Op = ast::ExprNode::Op;
  ast::Index base = ast::none;
  if (!primary(p, base)) return false;
  struct Tail {
    int minus = 0;
    std::uint32_t signs_at = 0;
    ast::Index operand = ast::none;
  };
  std::vector<Tail> tail;
  while (lit(p, '^')) {
    It start = p;
    Tail t;
    It q = skip(p);
    t.signs_at = off(q);
    for (;;) {
      q = skip(p);
      if (q < end_ && (*q == '+' || *q == '-')) {
        t.minus += *q == '-';
        p = q + 1;
      } else {
        break;
      }
    }
    if (!primary(p, t.operand)) fail(start, "exponent");
    tail.push_back(t);
  }
  if (tail.empty()) {
    out = base;
    return true;
  }
  const std::uint32_t begin = file_.exprs[base].begin, end = off(p);
  auto signed_operand = [&](const Tail& t) {
    return t.minus % 2 ? negate(t.operand, t.signs_at) : t.operand;
  };
  ast::Index exponent = signed_operand(tail.back());
  for (std::size_t i = tail.size() - 1; i-- > 0;) {
    ast::ExprNode n;
    n.op = Op::power;
    n.a = tail[i].operand;
    n.b = exponent;
    n.begin = begin;
    n.end = end;
    exponent = add(n);
    if (tail[i].minus % 2) exponent = negate(exponent, tail[i].signs_at);
  }
  ast::ExprNode n;
  n.op = Op::power;
  n.a = base;
  n.b = exponent;
  n.begin = begin;
  n.end = end;
  out = add(n);
  return true;
}

// Leading signs apply to the power; a signed number with a unit is one quantity (-10 [degC] is
// 263.15 K, not -(283.15 K)), so its sign is folded into the literal.
bool Grammar::signed_power(It& p, ast::Index& out) {
  It start = p;
  It q = skip(p);
  const std::uint32_t signs_at = off(q);
  int minus = 0;
  bool any = false;
  for (;;) {
    q = skip(p);
    if (q < end_ && (*q == '+' || *q == '-')) {
      minus += *q == '-';
      any = true;
      p = q + 1;
    } else {
      break;
    }
  }
  ast::Index operand = ast::none;
  if (!power(p, operand)) {
    p = start;
    return false;
  }
  ast::ExprNode& n = file_.exprs[operand];
  if (any && n.op == ast::ExprNode::Op::quantity) {
    if (minus % 2) n.value = -n.value;
    n.begin = signs_at;
    out = operand;
  } else if (minus % 2) {
    out = negate(operand, signs_at);
  } else if (any) { // only '+' signs: the value is unchanged, the span starts at the signs
    n.begin = signs_at;
    out = operand;
  } else {
    out = operand;
  }
  return true;
}

bool Grammar::term(It& p, ast::Index& out) {
  using Op = ast::ExprNode::Op;
  if (!signed_power(p, out)) return false;
  for (;;) {
    It q = skip(p);
    if (q == end_ || (*q != '*' && *q != '/')) return true;
    p = q + 1;
    ast::Index rhs = ast::none;
    if (!signed_power(p, rhs)) fail(p, "operand");
    ast::ExprNode n;
    n.op = *q == '*' ? Op::multiply : Op::divide;
    n.a = out;
    n.b = rhs;
    n.begin = file_.exprs[out].begin;
    n.end = file_.exprs[rhs].end;
    out = add(n);
  }
}

bool Grammar::expression(It& p, ast::Index& out) {
  using Op = ast::ExprNode::Op;
  if (!term(p, out)) return false;
  for (;;) {
    It q = skip(p);
    if (q == end_ || (*q != '+' && *q != '-')) return true;
    p = q + 1;
    ast::Index rhs = ast::none;
    if (!term(p, rhs)) fail(p, "operand");
    ast::ExprNode n;
    n.op = *q == '+' ? Op::add : Op::subtract;
    n.a = out;
    n.b = rhs;
    n.begin = file_.exprs[out].begin;
    n.end = file_.exprs[rhs].end;
    out = add(n);
  }
}

bool Grammar::expr(It& p, ast::Expr& out) {
  ast::Index root = ast::none;
  if (!expression(p, root)) return false;
  out = as_expr(root);
  return true;
}

void Grammar::expect_expr(It& p, ast::Expr& out, const char* what) {
  if (!expr(p, out)) fail(p, what);
}

// --- names ------------------------------------------------------------------------------------

// `[item, ...]` right after a name (no blank between); an item is an expression or `LO .. HI`.
bool Grammar::index_list(It& p, std::vector<ast::IndexItem>& out) {
  if (p == end_ || *p != '[') return false;
  ++p;
  do {
    ast::IndexItem item;
    if (!expr(p, item.lo)) fail(p, "index");
    item.begin = item.lo.begin;
    item.end = item.lo.end;
    It q = skip(p);
    if (end_ - q >= 2 && q[0] == '.' && q[1] == '.') {
      p = q + 2;
      ast::Expr hi;
      expect_expr(p, hi, "expression");
      item.end = hi.end;
      item.hi = hi;
    }
    out.push_back(std::move(item));
  } while (lit(p, ','));
  expect(p, ']', "']'");
  return true;
}

// A name, its index list and further `.name[...]` parts. Outside a case target the dot must join
// the parts without blanks (`a .5` is a name and a number); in a case target it may be spaced
// (`film . P`), as the core language allows there.
bool Grammar::ref(It& p, ast::Ref& out, bool target) {
  if (!identifier(p, out.id)) return false;
  out.begin = out.id.begin;
  std::vector<ast::IndexItem> index;
  std::vector<ast::Ref> rest;
  index_list(p, index);
  for (;;) {
    It q = target ? skip(p) : p;
    if (q == end_ || *q != '.') break;
    if (!target && !(q + 1 < end_ && is_ident_start(q[1]))) break;
    It r = q + 1;
    ast::Ref part;
    if (!identifier(r, part.id)) fail(r, "name");
    part.begin = part.id.begin;
    std::vector<ast::IndexItem> part_index;
    if (index_list(r, part_index)) {
      part.tail = std::make_unique<ast::RefTail>();
      part.tail->index = std::move(part_index);
    }
    part.end = off(r);
    rest.push_back(std::move(part));
    p = r;
  }
  out.end = off(p);
  if (!index.empty() || !rest.empty()) {
    out.tail = std::make_unique<ast::RefTail>();
    out.tail->index = std::move(index);
    out.tail->rest = std::move(rest);
  }
  return true;
}

bool Grammar::decl_name(It& p, ast::Ref& out) {
  if (!identifier(p, out.id)) return false;
  out.begin = out.id.begin;
  std::vector<ast::IndexItem> index;
  if (index_list(p, index)) {
    out.tail = std::make_unique<ast::RefTail>();
    out.tail->index = std::move(index);
  }
  out.end = off(p);
  return true;
}

// A terminal node: a name not followed by '=' (it is a key) nor by a number or an operator (it is
// a key whose '=' is missing, `G 2`).
bool Grammar::terminal(It& p, ast::Ref& out) {
  It start = p;
  if (!ref(p, out, false)) return false;
  It q = skip(p);
  if (q < end_ && (*q == '=' || is_digit(*q) || *q == '(' || *q == '+' || *q == '-' || *q == '.')) {
    p = start;
    out = ast::Ref{};
    return false;
  }
  return true;
}

// --- values -----------------------------------------------------------------------------------

bool Grammar::point_signal(It& p, ast::Value& out) {
  It start = p;
  It q = skip(p);
  ast::Identifier kind;
  if (at_word(q, "step") || at_word(q, "pwl")) {
    identifier(p, kind);
  } else {
    return false;
  }
  if (!lit(p, '(')) {
    p = start;
    return false;
  }
  std::vector<ast::SignalPoint> points;
  auto point = [&](bool required) {
    ast::SignalPoint pt;
    It at = p;
    if (!expr(p, pt.time)) {
      if (required) fail(at, "'time: value' point");
      return false;
    }
    expect(p, ':', "':'");
    expect_expr(p, pt.value, "expression");
    pt.begin = pt.time.begin;
    pt.end = pt.value.end;
    points.push_back(std::move(pt));
    return true;
  };
  if (!point(false)) {
    p = start;
    return false;
  }
  while (lit(p, ','))
    point(true);
  expect(p, ')', "')'");
  ast::PointSignal s;
  s.kind = kind;
  s.points = std::move(points);
  s.begin = kind.begin;
  s.end = off(p);
  out.other = std::make_unique<ast::Value::Other>(std::move(s));
  return true;
}

bool Grammar::table_signal(It& p, ast::Value& out) {
  It start = p;
  It q = skip(p);
  if (!kw(p, "table") || !lit(p, '(')) {
    p = start;
    return false;
  }
  ast::TableSignal t;
  if (!string_literal(p, t.file)) {
    p = start;
    return false;
  }
  expect(p, ',', "','");
  if (!string_literal(p, t.column)) fail(p, "string");
  expect(p, ')', "')'");
  t.begin = off(q);
  t.end = off(p);
  out.other = std::make_unique<ast::Value::Other>(std::move(t));
  return true;
}

bool Grammar::value(It& p, ast::Value& out) {
  if (point_signal(p, out) || table_signal(p, out)) return true;
  // A name with an index or dots is a node reference (`sense = p[3]`), never an expression.
  It q = skip(p);
  if (q < end_ && is_ident_start(*q)) {
    It r = q;
    while (r < end_ && is_ident_char(*r))
      ++r;
    if (r < end_ && (*r == '[' || (*r == '.' && r + 1 < end_ && is_ident_start(r[1])))) {
      ast::Ref ref_value;
      ref(p, ref_value, false);
      out.other = std::make_unique<ast::Value::Other>(std::move(ref_value));
      return true;
    }
  }
  return expr(p, out.expr);
}

void Grammar::expect_value(It& p, ast::Value& out) {
  if (!value(p, out)) fail(p, "value");
}

bool Grammar::key_value(It& p, ast::KeyValue& out) {
  if (!identifier(p, out.key)) return false;
  expect(p, '=', "'='");
  expect_value(p, out.value);
  out.begin = out.key.begin;
  out.end = out.value.span().end;
  return true;
}

void Grammar::keys(It& p, std::vector<ast::KeyValue>& out) {
  const std::size_t from = key_scratch_.size();
  for (;;) {
    key_scratch_.emplace_back();
    if (!key_value(p, key_scratch_.back())) {
      key_scratch_.pop_back();
      break;
    }
  }
  out = take(key_scratch_, from);
}

void Grammar::doc(It& p, std::unique_ptr<ast::String>& out) {
  ast::String s;
  if (string_literal(p, s)) out = std::make_unique<ast::String>(std::move(s));
}

// --- statements -------------------------------------------------------------------------------

bool Grammar::param(It& p, ast::ParamStmt& out, Place place) {
  expect_identifier(p, out.name);
  // In a submodel a param may be left without a value: each instance must then give one.
  const bool value_optional = place == Place::submodel;
  if (lit(p, '=')) {
    expect_expr(p, out.value, "expression");
  } else if (!value_optional) {
    fail(p, "'='");
  }
  if (out.value.valid() && kw(p, "range")) {
    ast::Range r;
    It at = p;
    if (!expr(p, r.lo)) fail(at, "range 'LO .. HI'");
    It q = skip(p);
    if (!(end_ - q >= 2 && q[0] == '.' && q[1] == '.')) fail(p, "\"..\"");
    p = q + 2;
    expect_expr(p, r.hi, "expression");
    r.begin = r.lo.begin;
    r.end = r.hi.end;
    out.range = std::move(r);
  }
  doc(p, out.doc);
  return true;
}

bool Grammar::node(It& p, ast::NodeStmt& out) {
  if (!decl_name(p, out.name)) fail(p, "name");
  keys(p, out.keys);
  doc(p, out.doc);
  return true;
}

bool Grammar::composite(It& p, ast::CompositeStmt& out) {
  if (!decl_name(p, out.name)) fail(p, "name");
  It pair = p;
  for (int i = 0; i < 2; ++i) {
    ast::Ref r;
    if (!ref(p, r, false)) {
      out.nodes.clear();
      fail(pair, "the two terminal nodes");
    }
    out.nodes.push_back(std::move(r));
  }
  while (eol(p)) {
  }
  expect(p, '{', "'{'");
  auto separators = [&] {
    for (;;) {
      if (lit(p, ';') || eol(p)) continue;
      return;
    }
  };
  separators();
  for (;;) {
    ast::InnerElement part;
    if (!identifier(p, part.kind)) break;
    keys(p, part.keys);
    part.begin = part.kind.begin;
    part.end = part.keys.empty() ? part.kind.end : part.keys.back().end;
    out.parts.push_back(std::move(part));
    separators();
  }
  expect(p, '}', "'}'");
  return true;
}

bool Grammar::element(It& p, ast::ElementStmt& out) {
  It start = p;
  if (!identifier(p, out.kind) || !decl_name(p, out.name)) {
    p = start;
    return false;
  }
  const std::size_t from = ref_scratch_.size();
  for (;;) {
    ref_scratch_.emplace_back();
    if (!terminal(p, ref_scratch_.back())) {
      ref_scratch_.pop_back();
      break;
    }
  }
  out.nodes = take(ref_scratch_, from);
  keys(p, out.keys);
  doc(p, out.doc);
  return true;
}

bool Grammar::statement(It& p, ast::Statement& out, Place place) {
  key_scratch_.clear();
  ref_scratch_.clear();
  It q = skip(p);
  if (q == end_ || !is_ident_start(*q)) return false;
  It w = q;
  while (w < end_ && is_ident_char(*w))
    ++w;
  const std::string_view word(q, static_cast<std::size_t>(w - q));
  if (word == "model") {
    p = w;
    ast::ModelStmt s;
    expect_identifier(p, s.name);
    out = std::move(s);
  } else if (word == "include" || word == "plugin") {
    p = w;
    ast::String path;
    if (!string_literal(p, path)) fail(p, "string");
    if (word == "include")
      out = ast::IncludeStmt{{}, std::move(path)};
    else
      out = ast::PluginStmt{{}, std::move(path)};
  } else if (word == "const") {
    p = w;
    ast::ConstStmt s;
    expect_identifier(p, s.name);
    expect(p, '=', "'='");
    expect_expr(p, s.value, "expression");
    out = std::move(s);
  } else if (word == "param") {
    p = w;
    ast::ParamStmt s;
    param(p, s, place);
    out = std::move(s);
  } else if (word == "node" || word == "boundary") {
    p = w;
    ast::NodeStmt s;
    s.boundary = word == "boundary";
    node(p, s);
    out = std::move(s);
  } else if (word == "series" || word == "parallel") {
    ast::CompositeStmt s;
    identifier(p, s.mode);
    composite(p, s);
    out = std::move(s);
  } else {
    ast::ElementStmt s;
    if (!element(p, s)) return false;
    out = std::move(s);
  }
  return true;
}

// --- blocks -----------------------------------------------------------------------------------

bool Grammar::case_header(It& p, ast::Identifier& name) {
  if (!kw(p, "case")) return false;
  expect_identifier(p, name);
  while (eol(p)) {
  }
  expect(p, '{', "'{'");
  return true;
}

// `VAR in LO .. HI`; before the first `..` of a loop is seen nothing is certain (an element of a
// plugin kind called `for` reads `for NAME NODE ...`), so the first range commits only there.
bool Grammar::loop_range(It& p, ast::LoopRange& out, bool committed) {
  It start = p;
  if (!identifier(p, out.var)) {
    if (committed) fail(p, "name");
    return false;
  }
  if (!kw(p, "in")) {
    if (committed) fail(p, "'in'");
    p = start;
    return false;
  }
  if (!expr(p, out.lo)) {
    if (committed) fail(p, "expression");
    p = start;
    return false;
  }
  It q = skip(p);
  if (!(end_ - q >= 2 && q[0] == '.' && q[1] == '.')) {
    if (committed) fail(p, "\"..\"");
    p = start;
    return false;
  }
  p = q + 2;
  expect_expr(p, out.hi, "expression");
  out.begin = out.var.begin;
  out.end = out.hi.end;
  return true;
}

bool Grammar::loop_header(It& p, std::vector<ast::LoopRange>& ranges) {
  It start = p;
  if (!kw(p, "for")) return false;
  ast::LoopRange first;
  if (!loop_range(p, first, false)) {
    p = start;
    return false;
  }
  ranges.push_back(std::move(first));
  while (lit(p, ',')) {
    ast::LoopRange r;
    loop_range(p, r, true);
    ranges.push_back(std::move(r));
  }
  while (eol(p)) {
  }
  expect(p, '{', "'{'");
  return true;
}

bool Grammar::submodel_header(It& p, ast::SubmodelStmt& out) {
  It start = p;
  if (!kw(p, "submodel") || !identifier(p, out.name) || !lit(p, '(')) {
    p = start;
    out.name = {};
    return false;
  }
  ast::Identifier t;
  if (identifier(p, t)) {
    out.terminals.push_back(t);
    while (lit(p, ',')) {
      expect_identifier(p, t);
      out.terminals.push_back(t);
    }
  }
  expect(p, ')', "')'");
  while (eol(p)) {
  }
  expect(p, '{', "'{'");
  return true;
}

bool Grammar::case_data(It& p, ast::CaseData& out) {
  It start = p;
  if (!kw(p, "data")) return false;
  It q = skip(p);
  if (q < end_ && (*q == '=' || *q == '.')) { // a param or node called `data`
    p = start;
    return false;
  }
  if (!string_literal(p, out.path)) fail(p, "string");
  ast::UnitText u;
  if (unit(p, u)) out.unit = std::move(u);
  return true;
}

bool Grammar::case_assign(It& p, ast::CaseAssign& out) {
  if (!ref(p, out.target.path, true)) return false;
  out.target.begin = out.target.path.begin;
  out.target.end = out.target.path.end;
  expect(p, '=', "'='");
  expect_value(p, out.value);
  while (lit(p, ',')) {
    ast::Expr e;
    expect_expr(p, e, "expression");
    out.more.push_back(e);
  }
  return true;
}

bool Grammar::case_item(It& p, ast::CaseItem& out) {
  key_scratch_.clear();
  ast::CaseData d;
  if (case_data(p, d)) {
    out = std::move(d);
    return true;
  }
  ast::CaseAssign a;
  if (case_assign(p, a)) {
    out = std::move(a);
    return true;
  }
  return false;
}

} // namespace thermnet::lang::grammar
