#pragma once
/// The Spirit X3 rules of the netlist language (included only by grammar.cpp).
///
/// No rule synthesises a syntax-tree attribute by itself: every rule has semantic actions, so X3
/// parses its right-hand side without attribute and the actions move what was matched into the
/// rule's own small attribute (`_val`) or build expression nodes straight into the file through
/// the Builder in the context. A statement is thus filled in place and moved once into the file.
///
/// Newlines end statements, so the skipper (line_space) skips blanks, comments and `\`
/// continuations but not newlines. After a keyword the rest is certain: `>` makes a missing part an
/// x3::expectation_failure naming it as the messages do ("'='", "value", "operand"), which is why
/// a few rules exist only to carry such a name. Recursive rules are never used inside lexeme[] or
/// no_skip[] (that would instantiate them again for every other skipper).

#include "lang/grammar_x3_builder.hpp"

#include <boost/spirit/home/x3.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace boost::spirit::x3 {
/// A parser with a semantic action is described as its subject, so that `> rule[action]` fails
/// naming the rule ("'='", "value"), not a C++ type.
template <typename Subject, typename Action> struct get_info<action<Subject, Action>> {
  using result_type = std::string;
  std::string operator()(const action<Subject, Action>& p) const { return what(p.subject); }
};
} // namespace boost::spirit::x3

namespace thermnet::lang::grammar::x3_rules {

namespace x3 = boost::spirit::x3;
using x3::_attr;
using x3::_val;
using x3::eps;
using x3::lexeme;
using x3::lit;
using x3::raw;
using Op = ast::ExprNode::Op;

/// Context tag of the Builder the semantic actions write into.
struct builder_tag;

/// The Builder of the parse in progress.
template <typename Context> Builder& builder(const Context& ctx) {
  return x3::get<builder_tag>(ctx);
}

// --- lexical ----------------------------------------------------------------------------------

// Character classes as byte sets (x3::alpha and friends call the C classification functions,
// which must not see the negative chars of UTF-8 bytes); names are ASCII.
inline const auto ident_start = x3::char_("a-zA-Z_");
inline const auto ident_char = x3::char_("a-zA-Z0-9_");
inline const auto digits = +x3::char_("0-9");

/// The skipper: a run of blanks, '\r', comments and `\` continuations; newlines stay significant.
/// It runs before every token, so it is one primitive parser with a plain loop rather than an
/// alternative of X3 parsers (`char_(" \t\r") | '#' >> *~char_("\n\r") | '\\' >> *blank >> eol`),
/// which X3 would try one by one for each character (a tenth of the parse time).
struct line_space_parser : x3::parser<line_space_parser> {
  using attribute_type = x3::unused_type;
  static const bool has_attribute = false;

  template <typename Iterator, typename Context, typename RContext, typename Attribute>
  bool parse(Iterator& first, const Iterator& last, const Context&, RContext&, Attribute&) const {
    Iterator p = first;
    while (p != last) {
      if (*p == ' ' || *p == '\t' || *p == '\r') {
        ++p;
      } else if (*p == '#') {
        while (p != last && *p != '\n' && *p != '\r')
          ++p;
      } else if (*p == '\\') {
        Iterator q = p + 1;
        while (q != last && (*q == ' ' || *q == '\t'))
          ++q;
        if (q == last || (*q != '\n' && *q != '\r')) break;
        p = *q == '\r' && q + 1 != last && q[1] == '\n' ? q + 2 : q + 1;
      } else {
        break;
      }
    }
    const bool skipped = p != first;
    first = p;
    return skipped;
  }
};
inline const line_space_parser line_space{};

/// A keyword only as a whole word (`node` but not `node2`).
inline auto keyword(const char* word) {
  return lexeme[lit(word) >> !ident_char];
}

/// A decimal point: a '.' followed by another '.' is a range (`1..10`).
inline const auto decimal_point = lit('.') >> !lit('.');
/// An unsigned real: a leading dot is allowed, a trailing one is not; never glued to letters or
/// to a further '.' (so `3mm` and `1.2.3` are not numbers, while `1..10` is a range).
/// (Used inside lexeme[].)
inline const auto number_token = ((digits >> -(decimal_point >> digits)) |
                                  (decimal_point >> digits)) >>
                                 -(x3::char_("eE") >> -x3::char_("+-") >> digits) >>
                                 !(ident_char | decimal_point);

/// The words that start a statement (no element kind may be called so).
inline const x3::symbols<> statement_keywords({"model", "include", "plugin", "const", "param",
                                               "node", "boundary", "series", "parallel"});
/// The operators of a term and of a sum.
inline const x3::symbols<Op> multiplicative({{"*", Op::multiply}, {"/", Op::divide}});
inline const x3::symbols<Op> additive({{"+", Op::add}, {"-", Op::subtract}});

// --- attributes that carry a rule's locals ----------------------------------------------------

/// The signs before an operand: where they start, how many are '-', whether there are any.
struct Signs {
  std::uint32_t at = 0; ///< offset of the first sign (or of the operand when none)
  int minus = 0;        ///< number of '-'
  bool any = false;     ///< at least one sign
};
/// A power chain being parsed: its base, then (when complete) the whole chain.
struct Chain {
  ast::Index root = ast::none; ///< base, then the chain's root
  std::size_t from = 0;        ///< where the chain's tails start in Builder::tails
};
/// A signed power: its signs, then the resulting node.
struct Signed {
  Signs signs;                 ///< the leading signs
  ast::Index root = ast::none; ///< the node
};
/// A name, or a call with its arguments (in Builder::args from `args_from`).
struct Callee {
  ast::Identifier id;        ///< the name
  std::size_t args_from = 0; ///< first argument in Builder::args
  std::uint32_t end = 0;     ///< end of the call's ')'
  bool call = false;         ///< a call, not a name
};
/// `op operand` after the first operand of a term or a sum.
struct Operation {
  Op op = Op::add;            ///< the operator
  ast::Index rhs = ast::none; ///< the right operand
};
/// The limit of a requirement: `LO .. HI`, `max VALUE` or `min VALUE`.
struct RequireLimit {
  ast::Identifier bound;       ///< `max` or `min` (empty for a range)
  std::optional<ast::Expr> lo; ///< the lower end of a range
  ast::Expr limit;             ///< the upper end of a range, or the value
};
/// A param's `= value [range LO .. HI]` (absent in a submodel).
struct ParamValue {
  ast::Expr value;                 ///< the value (invalid when left out)
  std::optional<ast::Range> range; ///< calibration range
};

/// One option of a table or data statement: `hold`, `time = ...` or `separator = ...`.
struct FileOption {
  enum class Which : std::uint8_t { hold, before, time, separator };
  Which which = Which::hold; ///< which option
  ast::Tagged at;            ///< where it is written
  ast::TimeOption time;      ///< `time = "COLUMN" [UNIT]`
  ast::String separator;     ///< `separator = "..."`
  ast::Expr before;          ///< `before = VALUE`
};

// --- rules ------------------------------------------------------------------------------------

// Rules whose name appears in messages carry it; the others are named for debugging only.
inline const x3::rule<class identifier_r, ast::Identifier> identifier = "name";
inline const x3::rule<class string_r, ast::String> string_literal = "string";
inline const x3::rule<class unit_r, ast::UnitText> unit = "unit";
inline const x3::rule<class quantity_r, ast::Index> quantity = "number";
inline const x3::rule<class callee_r, Callee> callee = "name or call";
inline const x3::rule<class primary_r, ast::Index> primary = "operand";
inline const x3::rule<class signs_r, Signs> signs = "signs";
inline const x3::rule<class exponent_r, PowerTail> exponent = "exponent";
inline const x3::rule<class power_r, Chain> power = "operand";
inline const x3::rule<class signed_r, Signed> signed_power = "operand";
inline const x3::rule<class factor_r, Operation> factor = "operand";
inline const x3::rule<class term_r, ast::Index> term = "operand";
inline const x3::rule<class summand_r, Operation> summand = "operand";
inline const x3::rule<class expression_r, ast::Index> expression = "expression";
inline const x3::rule<class index_item_r, ast::IndexItem> index_item = "index";
inline const x3::rule<class index_list_r, std::vector<ast::IndexItem>> index_list = "index list";
inline const x3::rule<class name_part_r, ast::Ref> name_part = "name";
inline const x3::rule<class ref_r, ast::Ref> ref = "node reference";
inline const x3::rule<class target_r, ast::Ref> target = "case setting";
inline const x3::rule<class terminal_r, ast::Ref> terminal = "terminal node";
inline const x3::rule<class point_r, ast::SignalPoint> signal_point = "'time: value' point";
inline const x3::rule<class point_signal_r, ast::PointSignal> point_signal = "signal";
inline const x3::rule<class table_signal_r, ast::TableSignal> table_signal = "table signal";
inline const x3::rule<class file_option_r, FileOption> file_option =
    "option ('hold', 'before = VALUE', 'time = \"COLUMN\" [UNIT]' or 'separator = \";\"')";
inline const x3::rule<class time_option_r, ast::TimeOption> time_option = "time column";
inline const x3::rule<class key_ref_r, ast::Ref> key_ref = "key reference";
inline const x3::rule<class column_name_r, ast::String> column_name = "column name";
inline const x3::rule<class column_source_r, ast::ColumnSource> column_source = "column";
inline const x3::rule<class column_map_r, ast::ColumnMap> column_map = "'NODE = COLUMN'";
inline const x3::rule<class value_r, ast::Value> value = "value";
inline const x3::rule<class key_value_r, ast::KeyValue> key_value = "key = value";
inline const x3::rule<class keys_r, std::span<const ast::KeyValue>> keys = "keys";
inline const x3::rule<class model_r, ast::ModelStmt> model_stmt = "model statement";
inline const x3::rule<class include_r, ast::IncludeStmt> include_stmt = "include statement";
inline const x3::rule<class plugin_r, ast::PluginStmt> plugin_stmt = "plugin statement";
inline const x3::rule<class const_r, ast::ConstStmt> const_stmt = "const statement";
inline const x3::rule<class range_r, ast::Range> range = "range 'LO .. HI'";
inline const x3::rule<class param_value_r, ParamValue> param_value = "'='";
inline const x3::rule<class param_r, ast::ParamStmt> param_stmt = "param statement";
inline const x3::rule<class node_r, ast::NodeStmt> node_stmt = "node statement";
inline const x3::rule<class element_r, ast::ElementStmt> element_stmt = "element statement";
inline const x3::rule<class inner_r, ast::InnerElement> inner_element = "inner element";
inline const x3::rule<class pair_r> terminal_pair = "the two terminal nodes";
inline const x3::rule<class composite_r, ast::CompositeStmt> composite_stmt = "series/parallel";
inline const x3::rule<class require_group_r, ast::String> require_group =
    "a node or element name or glob in quotes (\"lens*\")";
inline const x3::rule<class require_limit_r, RequireLimit> require_limit =
    "limit ('LO .. HI', 'max VALUE' or 'min VALUE')";
inline const x3::rule<class require_r, ast::RequireStmt> require_stmt = "require statement";
inline const x3::rule<class statement_r, ast::Statement> statement = "statement";
inline const x3::rule<class case_header_r, ast::Identifier> case_header = "'case NAME {'";
inline const x3::rule<class in_r> in_keyword = "'in'";
inline const x3::rule<class first_range_r, ast::LoopRange> first_loop_range = "loop range";
inline const x3::rule<class loop_range_r, ast::LoopRange> loop_range = "name";
inline const x3::rule<class loop_header_r, std::vector<ast::LoopRange>> loop_header = "for";
inline const x3::rule<class submodel_header_r, ast::SubmodelStmt> submodel_header = "submodel";
inline const x3::rule<class case_data_r, ast::CaseData> case_data = "data statement";
inline const x3::rule<class case_assign_r, ast::CaseAssign> case_assign = "case setting";
inline const x3::rule<class case_item_r, ast::CaseItem> case_item = "case statement";

// --- semantic actions -------------------------------------------------------------------------

/// Moves the matched attribute into the rule's attribute.
inline const auto take = [](auto& ctx) { _val(ctx) = std::move(_attr(ctx)); };
/// Sets `Member` of the rule's attribute to the matched attribute.
template <auto Member>
inline const auto set = [](auto& ctx) { _val(ctx).*Member = std::move(_attr(ctx)); };
/// Sets `Member` of the rule's attribute to the expression whose root was matched.
template <auto Member>
inline const auto set_expr = [](auto& ctx) { _val(ctx).*Member = builder(ctx).expr(_attr(ctx)); };
/// Appends the matched attribute to the rule's (vector) attribute.
inline const auto push = [](auto& ctx) { _val(ctx).push_back(std::move(_attr(ctx))); };
/// Sets the rule's Tagged span to the raw range matched.
inline const auto span = [](auto& ctx) {
  _val(ctx).begin = builder(ctx).off(_attr(ctx).begin());
  _val(ctx).end = builder(ctx).off(_attr(ctx).end());
};
/// Makes a statement's `doc` from the matched string.
inline const auto set_doc = [](auto& ctx) {
  _val(ctx).doc = std::make_unique<ast::String>(std::move(_attr(ctx)));
};

inline const auto make_identifier = [](auto& ctx) {
  _val(ctx) = builder(ctx).identifier(_attr(ctx).begin(), _attr(ctx).end());
};
inline const auto make_string = [](auto& ctx) {
  _val(ctx) = builder(ctx).string_literal(_attr(ctx).begin(), _attr(ctx).end());
};
inline const auto make_unit_text = [](auto& ctx) {
  auto& u = _val(ctx);
  u.begin = builder(ctx).off(_attr(ctx).begin());
  u.end = builder(ctx).off(_attr(ctx).end());
  u.text.assign(_attr(ctx).begin(), _attr(ctx).end());
};

// expressions
inline const auto make_number = [](auto& ctx) {
  _val(ctx) = builder(ctx).number(_attr(ctx).begin(), _attr(ctx).end());
};
// The quantity ends after the ']' (only skipped characters may stand between the text and it).
inline const auto attach_unit = [](auto& ctx) {
  Builder& b = builder(ctx);
  ast::ExprNode& n = b.file.exprs[_val(ctx)];
  const char* close = b.base + _attr(ctx).end;
  while (*close != ']')
    ++close;
  n.op = Op::quantity;
  n.a = static_cast<ast::Index>(b.file.units.size());
  n.end = b.off(close + 1);
  b.file.units.push_back(std::move(_attr(ctx)));
};
inline const auto start_args = [](auto& ctx) { _val(ctx).args_from = builder(ctx).args.size(); };
inline const auto push_arg = [](auto& ctx) { builder(ctx).args.push_back(_attr(ctx)); };
inline const auto close_call = [](auto& ctx) {
  _val(ctx).call = true;
  _val(ctx).end = builder(ctx).off(_attr(ctx).end());
};
inline const auto make_name_or_call = [](auto& ctx) {
  Builder& b = builder(ctx);
  const Callee& c = _attr(ctx);
  ast::ExprNode n;
  n.op = Op::name;
  n.a = static_cast<ast::Index>(b.file.names.size());
  n.begin = c.id.begin;
  n.end = c.id.end;
  if (c.call) {
    const auto first = b.args.begin() + static_cast<std::ptrdiff_t>(c.args_from);
    n.op = Op::call;
    n.b = static_cast<ast::Index>(b.file.args.size());
    n.end = c.end;
    b.file.args.push_back(static_cast<ast::Index>(b.args.end() - first)); // the count
    b.file.args.insert(b.file.args.end(), first, b.args.end());
    b.args.resize(c.args_from);
  }
  b.file.names.push_back(c.id);
  _val(ctx) = b.add(n);
};
inline const auto make_group = [](auto& ctx) {
  Builder& b = builder(ctx);
  _val(ctx) =
      b.add(Op::group, _val(ctx), ast::none, b.off(_attr(ctx).begin()), b.off(_attr(ctx).end()));
};
inline const auto count_signs = [](auto& ctx) {
  Signs& s = _val(ctx);
  s.at = builder(ctx).off(_attr(ctx).begin());
  for (char c : _attr(ctx)) {
    s.minus += c == '-';
    s.any = s.any || c == '-' || c == '+';
  }
};
inline const auto set_tail_signs = [](auto& ctx) {
  _val(ctx).minus = _attr(ctx).minus;
  _val(ctx).signs_at = _attr(ctx).at;
};
inline const auto start_chain = [](auto& ctx) {
  _val(ctx).root = _attr(ctx);
  _val(ctx).from = builder(ctx).tails.size();
};
inline const auto push_tail = [](auto& ctx) { builder(ctx).tails.push_back(_attr(ctx)); };
// `base ^ [signs] e1 ^ [signs] e2 ...` is right-associative; every power node of the chain spans
// the whole chain (as messages about it mark it).
inline const auto finish_chain = [](auto& ctx) {
  Builder& b = builder(ctx);
  Chain& chain = _val(ctx);
  if (b.tails.size() == chain.from) return;
  const std::uint32_t begin = b.file.exprs[chain.root].begin;
  const std::uint32_t end = b.file.exprs[b.tails.back().operand].end;
  auto signed_operand = [&](const PowerTail& t) {
    return t.minus % 2 ? b.negate(t.operand, t.signs_at) : t.operand;
  };
  ast::Index exponent = signed_operand(b.tails.back());
  for (std::size_t i = b.tails.size() - 1; i-- > chain.from;) {
    exponent = b.add(Op::power, b.tails[i].operand, exponent, begin, end);
    if (b.tails[i].minus % 2) exponent = b.negate(exponent, b.tails[i].signs_at);
  }
  chain.root = b.add(Op::power, chain.root, exponent, begin, end);
  b.tails.resize(chain.from);
};
// Leading signs apply to the power; a signed number with a unit is one quantity (-10 [degC] is
// 263.15 K, not -(283.15 K)), so its sign is folded into the literal.
inline const auto apply_signs = [](auto& ctx) {
  Builder& b = builder(ctx);
  const Signs& s = _val(ctx).signs;
  const ast::Index operand = _attr(ctx).root;
  ast::ExprNode& n = b.file.exprs[operand];
  _val(ctx).root = operand;
  if (s.any && n.op == Op::quantity) {
    if (s.minus % 2) n.value = -n.value;
    n.begin = s.at;
  } else if (s.minus % 2) {
    _val(ctx).root = b.negate(operand, s.at);
  } else if (s.any) { // only '+' signs: the value is unchanged, the span starts at the signs
    n.begin = s.at;
  }
};
inline const auto first_factor = [](auto& ctx) { _val(ctx) = _attr(ctx).root; };
inline const auto set_factor = [](auto& ctx) { _val(ctx).rhs = _attr(ctx).root; };
inline const auto apply_operation = [](auto& ctx) {
  _val(ctx) = builder(ctx).binary(_attr(ctx).op, _val(ctx), _attr(ctx).rhs);
};

// names
inline const auto index_hi = [](auto& ctx) {
  _val(ctx).hi = builder(ctx).expr(_attr(ctx));
  _val(ctx).end = _val(ctx).hi->end;
};
inline const auto index_lo = [](auto& ctx) {
  _val(ctx).lo = builder(ctx).expr(_attr(ctx));
  _val(ctx).begin = _val(ctx).lo.begin;
  _val(ctx).end = _val(ctx).lo.end;
};
inline const auto set_ref_id = [](auto& ctx) { _val(ctx).id = _attr(ctx); };
inline const auto set_ref_index = [](auto& ctx) {
  if (!_val(ctx).tail) _val(ctx).tail = std::make_unique<ast::RefTail>();
  _val(ctx).tail->index = std::move(_attr(ctx));
};
inline const auto push_ref_part = [](auto& ctx) {
  if (!_val(ctx).tail) _val(ctx).tail = std::make_unique<ast::RefTail>();
  _val(ctx).tail->rest.push_back(std::move(_attr(ctx)));
};

// signals and references in expressions
/// An expression node of kind `op` standing for the matched item, which is moved into the file's
/// list `pool` (the node's `a` is its index there).
template <Op op, auto pool>
inline const auto make_pooled_node = [](auto& ctx) {
  Builder& b = builder(ctx);
  auto& items = b.file.*pool;
  ast::ExprNode n;
  n.op = op;
  n.a = static_cast<ast::Index>(items.size());
  n.begin = _attr(ctx).begin;
  n.end = _attr(ctx).end;
  items.push_back(std::move(_attr(ctx)));
  _val(ctx) = b.add(n);
};
/// An expression node standing for the matched step/pwl or table signal.
inline const auto& make_signal_node = make_pooled_node<Op::signal, &ast::File::signals>;
/// An expression node standing for the matched reference to a key (`film.P`).
inline const auto& make_ref_node = make_pooled_node<Op::ref, &ast::File::expr_refs>;
inline const auto set_case_data_file = [](auto& ctx) { _val(ctx).case_data = true; };
inline const auto set_option_time = [](auto& ctx) { _val(ctx).time = std::move(_attr(ctx)); };
inline const auto set_option_separator = [](auto& ctx) {
  _val(ctx).separator = std::move(_attr(ctx));
};
inline const auto option_hold = [](auto& ctx) {
  _val(ctx).which = FileOption::Which::hold;
  _val(ctx).at.begin = builder(ctx).off(_attr(ctx).begin());
  _val(ctx).at.end = builder(ctx).off(_attr(ctx).end());
};
inline const auto option_time = [](auto& ctx) {
  _val(ctx).which = FileOption::Which::time;
  _val(ctx).at = _attr(ctx);
  _val(ctx).time = std::move(_attr(ctx));
};
inline const auto option_before = [](auto& ctx) {
  _val(ctx).which = FileOption::Which::before;
  _val(ctx).before = builder(ctx).expr(_attr(ctx));
};
inline const auto option_at = [](auto& ctx) {
  _val(ctx).at.begin = builder(ctx).off(_attr(ctx).begin());
  _val(ctx).at.end = builder(ctx).off(_attr(ctx).end());
};
inline const auto option_separator = [](auto& ctx) {
  _val(ctx).which = FileOption::Which::separator;
  _val(ctx).separator = std::move(_attr(ctx));
};
/// Applies an option to the table or data statement being parsed (an option given twice, or
/// `hold` in a data statement, is kept in `repeated` for the elaborator to report).
inline const auto apply_file_option = [](auto& ctx) {
  auto& target = _val(ctx);
  FileOption& o = _attr(ctx);
  ast::FileOptions& opts = target.options;
  bool repeated = false;
  if (o.which == FileOption::Which::hold || o.which == FileOption::Which::before) {
    if constexpr (std::is_same_v<std::decay_t<decltype(target)>, ast::TableSignal>) {
      if (o.which == FileOption::Which::hold) {
        repeated = target.hold;
        target.hold = true;
      } else {
        repeated = target.before.has_value();
        target.before = o.before;
      }
    } else {
      repeated = true; // no meaning in a data statement
    }
  } else if (o.which == FileOption::Which::time) {
    repeated = opts.time.has_value();
    if (!repeated) opts.time = std::move(o.time);
  } else {
    repeated = opts.separator.has_value();
    o.at = o.separator;
    if (!repeated) opts.separator = std::move(o.separator);
  }
  if (repeated) opts.misplaced.push_back(o.at);
};
/// Extends a table's span over the unit written after it.
inline const auto set_table_unit = [](auto& ctx) {
  Builder& b = builder(ctx);
  ast::TableSignal& t = _val(ctx);
  const char* close = b.base + _attr(ctx).end;
  while (*close != ']')
    ++close;
  t.end = b.off(close + 1);
  t.unit = std::move(_attr(ctx));
};
inline const auto make_name_string = [](auto& ctx) {
  ast::String s;
  s.begin = builder(ctx).off(_attr(ctx).begin());
  s.end = builder(ctx).off(_attr(ctx).end());
  s.text.assign(_attr(ctx).begin(), _attr(ctx).end());
  _val(ctx) = std::move(s);
};
inline const auto set_mean = [](auto& ctx) { _val(ctx).mean = true; };
inline const auto push_source = [](auto& ctx) {
  _val(ctx).sources.push_back(std::move(_attr(ctx)));
};
inline const auto set_weight = [](auto& ctx) { _val(ctx).weight = builder(ctx).expr(_attr(ctx)); };
inline const auto push_column_map = [](auto& ctx) {
  _val(ctx).columns.push_back(std::move(_attr(ctx)));
};
inline const auto set_mapped = [](auto& ctx) { _val(ctx).mapped = true; };

// values and statements
inline const auto set_value_ref = [](auto& ctx) {
  _val(ctx).ref = std::make_unique<ast::Ref>(std::move(_attr(ctx)));
};
inline const auto set_key_span = [](auto& ctx) {
  _val(ctx).begin = _val(ctx).key.begin;
  _val(ctx).end = _val(ctx).value.span().end;
};
inline const auto set_point_span = [](auto& ctx) {
  _val(ctx).begin = _val(ctx).time.begin;
  _val(ctx).end = _val(ctx).value.end;
};
inline const auto set_signal_end = [](auto& ctx) {
  _val(ctx).begin = _val(ctx).kind.begin;
  _val(ctx).end = builder(ctx).off(_attr(ctx).end());
};
/// Keeps a key in the statement's scratch list (keys never nest).
inline const auto push_key = [](auto& ctx) { builder(ctx).keys.push_back(std::move(_attr(ctx))); };
/// Keeps a terminal in the element's scratch list.
inline const auto push_terminal = [](auto& ctx) {
  builder(ctx).refs.push_back(std::move(_attr(ctx)));
};
/// Moves the statement's keys into the file's key lists.
inline const auto take_keys = [](auto& ctx) {
  _val(ctx) = builder(ctx).file.key_lists.append(builder(ctx).keys);
};
/// Moves the terminals into the file's reference lists, as the statement's (element or
/// series/parallel) nodes.
inline const auto take_terminals = [](auto& ctx) {
  _val(ctx).nodes = builder(ctx).file.ref_lists.append(builder(ctx).refs);
};
/// Keeps an inner element in the statement's scratch list (blocks never nest).
inline const auto push_part = [](auto& ctx) {
  builder(ctx).parts.push_back(std::move(_attr(ctx)));
};
inline const auto take_parts = [](auto& ctx) {
  _val(ctx).parts = builder(ctx).file.part_lists.append(builder(ctx).parts);
};
inline const auto only_in_submodel = [](auto& ctx) {
  x3::_pass(ctx) = builder(ctx).param_value_optional;
};
inline const auto take_param_value = [](auto& ctx) {
  _val(ctx).value = _attr(ctx).value;
  _val(ctx).range = std::move(_attr(ctx).range);
};
inline const auto set_range_span = [](auto& ctx) {
  _val(ctx).begin = _val(ctx).lo.begin;
  _val(ctx).end = _val(ctx).hi.end;
};
inline const auto set_boundary = [](auto& ctx) { _val(ctx).boundary = true; };
inline const auto set_inner_span = [](auto& ctx) {
  ast::InnerElement& e = _val(ctx);
  e.begin = e.kind.begin;
  e.end = e.keys.empty() ? e.kind.end : e.keys.back().end;
};
inline const auto set_loop_span = [](auto& ctx) {
  _val(ctx).begin = _val(ctx).var.begin;
  _val(ctx).end = _val(ctx).hi.end;
};
inline const auto set_target = [](auto& ctx) {
  ast::Target& t = _val(ctx).target;
  t.path = std::move(_attr(ctx));
  t.begin = t.path.begin;
  t.end = t.path.end;
};
inline const auto push_more = [](auto& ctx) {
  _val(ctx).more.push_back(builder(ctx).expr(_attr(ctx)));
};
inline const auto push_terminal_name = [](auto& ctx) { _val(ctx).terminals.push_back(_attr(ctx)); };
inline const auto push_point = [](auto& ctx) { _val(ctx).points.push_back(std::move(_attr(ctx))); };
inline const auto push_group = [](auto& ctx) { _val(ctx).groups.push_back(std::move(_attr(ctx))); };
inline const auto push_case = [](auto& ctx) { _val(ctx).cases.push_back(_attr(ctx)); };
inline const auto take_limit = [](auto& ctx) {
  _val(ctx).bound = _attr(ctx).bound;
  _val(ctx).lo = _attr(ctx).lo;
  _val(ctx).limit = _attr(ctx).limit;
};

// --- definitions: lexical ---------------------------------------------------------------------

// lexeme[raw[...]] rather than raw[lexeme[...]]: both skip before the token, this one only once.
inline const auto identifier_def = lexeme[raw[ident_start >> *ident_char]][make_identifier];
// Only \\ and \" are escapes; any other backslash, a newline or the end stops the string there.
inline const auto string_literal_def =
    lexeme[raw[(lit('"') >> *((lit('\\') >> x3::char_("\\\"")) | ~x3::char_("\"\\\n\r"))) >
               lit('"')]][make_string];
inline const auto unit_def = (lit('[') >> lexeme[raw[*~x3::char_("[]\n\r")]][make_unit_text]) >
                             lit(']');

// --- definitions: expressions -----------------------------------------------------------------

inline const auto quantity_def = lexeme[raw[number_token]][make_number] >> -unit[attach_unit];
inline const auto callee_def =
    identifier[set<&Callee::id>] >>
    -raw[(lit('(') >> eps[start_args] >>
          -(expression[push_arg] >> *(lit(',') > expression[push_arg]))) > lit(')')][close_call];
// A name joined to a '[' or to '.' and a name is a reference (`film.P`, `h[3].P`), never a call.
inline const auto ref_start =
    &lexeme[ident_start >> *ident_char >> (lit('[') | (lit('.') >> ident_start))];
inline const auto key_ref_def = ref_start >> ref[take];
inline const auto primary_def = quantity[take] | point_signal[make_signal_node] |
                                table_signal[make_signal_node] | key_ref[make_ref_node] |
                                callee[make_name_or_call] |
                                raw[(lit('(') >> expression[take]) > lit(')')][make_group];
inline const auto signs_def = raw[*x3::char_("+-")][count_signs];
inline const auto exponent_def = signs[set_tail_signs] >> primary[set<&PowerTail::operand>];
inline const auto power_def = primary[start_chain] >>
                              *(lit('^') > exponent[push_tail]) >> eps[finish_chain];
inline const auto signed_power_def = signs[set<&Signed::signs>] >> power[apply_signs];
inline const auto factor_def = multiplicative[set<&Operation::op>] > signed_power[set_factor];
inline const auto term_def = signed_power[first_factor] >> *factor[apply_operation];
inline const auto summand_def = additive[set<&Operation::op>] > term[set<&Operation::rhs>];
inline const auto expression_def = term[take] >> *summand[apply_operation];

// --- definitions: names -----------------------------------------------------------------------

inline const auto index_item_def = expression[index_lo] >> -(lit("..") > expression[index_hi]);
// The '[' must follow the name without a blank.
inline const auto index_list_def = x3::no_skip[lit('[')] > index_item[push] >
                                   *(lit(',') > index_item[push]) > lit(']');
inline const auto name_part_def = raw[identifier[set_ref_id] >> -index_list[set_ref_index]][span];
// Outside a case target the dot must join the parts without blanks (`a .5` is a name and a
// number); in a case target it may be spaced (`film . P`), as the core language allows there.
inline const auto ref_def =
    raw[identifier[set_ref_id] >> -index_list[set_ref_index] >>
        *(x3::no_skip[lit('.') >> &ident_start] >> name_part[push_ref_part])][span];
inline const auto target_def = raw[identifier[set_ref_id] >> -index_list[set_ref_index] >>
                                   *(lit('.') > name_part[push_ref_part])][span];
// A terminal node: a name not followed by '=' (it is a key) nor by a number or an operator (it is
// a key whose '=' is missing, `G 2`).
inline const auto terminal_def = ref[take] >> !x3::char_("-=(+.0-9");

// --- definitions: values ----------------------------------------------------------------------

inline const auto signal_point_def = (expression[set_expr<&ast::SignalPoint::time>] > lit(':') >
                                      expression[set_expr<&ast::SignalPoint::value>]) >>
                                     eps[set_point_span];
// `step(` or `pwl(` followed by something else than a point is a call (of an unknown function).
inline const auto point_signal_def =
    raw[((&keyword("step") | &keyword("pwl")) >> identifier[set<&ast::PointSignal::kind>] >>
         lit('(') >> signal_point[push_point] >> *(lit(',') > signal_point[push_point])) > lit(')')]
       [set_signal_end];
inline const auto time_option_def =
    raw[(keyword("time") >> lit('=')) > string_literal[set<&ast::TimeOption::column>] >
        -unit[set<&ast::TimeOption::unit>]][span];
inline const auto file_option_def =
    raw[keyword("hold")][option_hold] | time_option[option_time] |
    ((keyword("separator") > lit('=')) > string_literal[option_separator]) |
    raw[(keyword("before") > lit('=')) > expression[option_before]][option_at];
// `table(` followed by something else than a file name or `data` is a call (of an unknown
// function); after the file, the rest is certain.
inline const auto table_signal_def =
    raw[(keyword("table") >> lit('(') >>
         (string_literal[set<&ast::TableSignal::file>] | keyword("data")[set_case_data_file])) >
        lit(',') > string_literal[set<&ast::TableSignal::column>] >
        *(lit(',') > file_option[apply_file_option]) > lit(')')][span] >>
    -unit[set_table_unit];
// A lone name with an index or dots is a reference (`sense = p[3]`, `P = film.P`); followed by an
// operator it is part of an expression.
inline const auto value_def = (ref_start >> ref >> !x3::char_("-+*/^"))[set_value_ref] |
                              expression[set_expr<&ast::Value::expr>];
inline const auto key_value_def =
    (identifier[set<&ast::KeyValue::key>] > lit('=') > value[set<&ast::KeyValue::value>]) >>
    eps[set_key_span];
inline const auto keys_def = *key_value[push_key] >> eps[take_keys];

// --- definitions: statements ------------------------------------------------------------------

inline const auto model_stmt_def = keyword("model") > identifier[set<&ast::ModelStmt::name>];
inline const auto include_stmt_def =
    keyword("include") > string_literal[set<&ast::IncludeStmt::path>];
inline const auto plugin_stmt_def = keyword("plugin") > string_literal[set<&ast::PluginStmt::path>];
inline const auto const_stmt_def = keyword("const") > identifier[set<&ast::ConstStmt::name>] >
                                   lit('=') > expression[set_expr<&ast::ConstStmt::value>];
inline const auto range_def =
    (expression[set_expr<&ast::Range::lo>] > lit("..") > expression[set_expr<&ast::Range::hi>]) >>
    eps[set_range_span];
// In a submodel a param may be left without a value: each instance must then give one.
inline const auto param_value_def = (lit('=') > expression[set_expr<&ParamValue::value>] >
                                     -(keyword("range") > range[set<&ParamValue::range>])) |
                                    eps[only_in_submodel];
inline const auto param_stmt_def = keyword("param") > identifier[set<&ast::ParamStmt::name>] >
                                   param_value[take_param_value] > -string_literal[set_doc];
inline const auto node_stmt_def = (keyword("node") | keyword("boundary")[set_boundary]) >
                                  name_part[set<&ast::NodeStmt::name>] >
                                  keys[set<&ast::NodeStmt::keys>] > -string_literal[set_doc];
inline const auto set_element_mean = [](auto& ctx) { _val(ctx).mean = true; };
// `sensor s mean(a, b)`: a sensor reading the mean of several nodes.
inline const auto mean_terminals = (keyword("mean") >> lit('('))[set_element_mean] >
                                   ref[push_terminal] > *(lit(',') > ref[push_terminal]) > lit(')');
inline const auto element_stmt_def = identifier[set<&ast::ElementStmt::kind>] >>
                                     name_part[set<&ast::ElementStmt::name>] >>
                                     (mean_terminals | *terminal[push_terminal]) >>
                                     eps[take_terminals] >> keys[set<&ast::ElementStmt::keys>] >>
                                     -string_literal[set_doc];
inline const auto inner_element_def =
    (identifier[set<&ast::InnerElement::kind>] >> keys[set<&ast::InnerElement::keys>]) >>
    eps[set_inner_span];
inline const auto terminal_pair_def = ref[push_terminal] >> ref[push_terminal];
inline const auto separators = *(lit(';') | lit('\n'));
inline const auto composite_stmt_def = (&(keyword("series") | keyword("parallel")) >>
                                        identifier[set<&ast::CompositeStmt::mode>]) >
                                       name_part[set<&ast::CompositeStmt::name>] > terminal_pair >
                                       eps[take_terminals] > *lit('\n') > lit('{') > separators >
                                       (*(inner_element[push_part] >> separators) >>
                                        eps[take_parts]) > lit('}');
// `require` is a statement only before a requirement kind (an element kind may be called so).
inline const x3::symbols<> requirement_kinds({"band", "gradient", "power", "energy", "margin"});
inline const auto require_group_def = string_literal[take];
inline const auto require_limit_def =
    ((&(keyword("max") | keyword("min")) >> identifier[set<&RequireLimit::bound>]) >
     expression[set_expr<&RequireLimit::limit>]) |
    (expression[set_expr<&RequireLimit::lo>] > lit("..") >
     expression[set_expr<&RequireLimit::limit>]);
inline const auto
    require_stmt_def = (keyword("require") >> &lexeme[requirement_kinds >> !ident_char]) >
                       identifier[set<&ast::RequireStmt::kind>] > require_group[push_group] >
                       *require_group[push_group] > require_limit[take_limit] >
                       -(keyword("from") > expression[set_expr<&ast::RequireStmt::from>]) >
                       -(in_keyword > identifier[push_case] > *(lit(',') > identifier[push_case])) >
                       -string_literal[set_doc];
// A statement keyword commits to its statement (each throws when the rest is wrong); any other
// first word is an element kind.
inline const auto statement_def =
    (&lexeme[statement_keywords >> !ident_char] >>
     (node_stmt[take] | composite_stmt[take] | param_stmt[take] | const_stmt[take] |
      model_stmt[take] | include_stmt[take] | plugin_stmt[take])) |
    require_stmt[take] | element_stmt[take];

// --- definitions: blocks ----------------------------------------------------------------------

inline const auto case_header_def = keyword("case") > identifier[take] > *lit('\n') > lit('{');
inline const auto in_keyword_def = keyword("in");
// Before the first `..` of a loop nothing is certain (an element of a plugin kind called `for`
// reads `for NAME NODE ...`), so only the later ranges are expected in full.
inline const auto first_loop_range_def = ((identifier[set<&ast::LoopRange::var>] >> in_keyword >>
                                           expression[set_expr<&ast::LoopRange::lo>] >> lit("..")) >
                                          expression[set_expr<&ast::LoopRange::hi>]) >>
                                         eps[set_loop_span];
inline const auto loop_range_def = (identifier[set<&ast::LoopRange::var>] > in_keyword >
                                    expression[set_expr<&ast::LoopRange::lo>] > lit("..") >
                                    expression[set_expr<&ast::LoopRange::hi>]) >>
                                   eps[set_loop_span];
inline const auto loop_header_def = (keyword("for") >> first_loop_range[push]) >
                                    *(lit(',') > loop_range[push]) > *lit('\n') > lit('{');
inline const auto submodel_header_def = (keyword("submodel") >>
                                         identifier[set<&ast::SubmodelStmt::name>] >> lit('(')) >
                                        -(identifier[push_terminal_name] >
                                          *(lit(',') > identifier[push_terminal_name])) > lit(')') >
                                        *lit('\n') > lit('{');
// `data` is a keyword only when not followed by '=' or '.' (a param or node may be called data).
inline const auto column_name_def =
    string_literal[take] | lexeme[raw[ident_start >> *ident_char]][make_name_string];
inline const auto column_source_def =
    raw[column_name[set<&ast::ColumnSource::column>] >> -(lit(':') > expression[set_weight])][span];
inline const auto column_map_def =
    raw[ref[set<&ast::ColumnMap::target>] > lit('=') >
        (((keyword("mean") >> lit('('))[set_mean] > column_source[push_source] >
          *(lit(',') > column_source[push_source]) > lit(')')) |
         column_source[push_source]) > -unit[set<&ast::ColumnMap::unit>]][span];
// `data` is a keyword only when not followed by '=' or '.' (a param or node may be called data).
inline const auto case_data_def = (keyword("data") >> !(lit('=') | lit('.'))) >
                                  string_literal[set<&ast::CaseData::path>] >
                                  -unit[set<&ast::CaseData::unit>] >
                                  *file_option[apply_file_option] >
                                  -((*lit('\n') >> lit('{'))[set_mapped] > separators >
                                    *(column_map[push_column_map] >> separators) > lit('}'));
inline const auto set_case_range = [](auto& ctx) {
  _val(ctx).range = std::make_unique<ast::Range>(std::move(_attr(ctx)));
};
inline const auto case_assign_def = target[set_target] >
                                    lit('=') > value[set<&ast::CaseAssign::value>] >
                                    *(lit(',') > expression[push_more]) >
                                    -(keyword("range") > range[set_case_range]);
inline const auto case_item_def = case_data[take] | case_assign[take];

BOOST_SPIRIT_DEFINE(identifier, string_literal, unit, quantity, callee, primary, signs, exponent,
                    power, signed_power, factor, term, summand, expression, index_item, index_list,
                    name_part, ref, target, terminal, signal_point, point_signal, table_signal,
                    file_option, time_option, key_ref, column_name, column_source, column_map,
                    value, key_value, keys, model_stmt, include_stmt, plugin_stmt, const_stmt,
                    range, param_value, param_stmt, node_stmt, element_stmt, inner_element,
                    terminal_pair, composite_stmt, require_group, require_limit, require_stmt,
                    statement, case_header, in_keyword, first_loop_range, loop_range, loop_header,
                    submodel_header, case_data, case_assign, case_item)

} // namespace thermnet::lang::grammar::x3_rules
