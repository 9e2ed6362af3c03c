#pragma once
/// The X3 grammar of the netlist language (included only by parser.cpp, where the rules are used).
///
/// Newlines end statements, so the skipper skips blanks, comments and `\` continuations but not
/// newlines. The driver hands the grammar a copy of the text in which newlines and comments inside
/// ( ) and [ ] are blanked (offsets unchanged), because switching skippers inside recursive X3
/// rules makes the context type grow without end.

#include "lang/ast.hpp"

#include <boost/fusion/include/adapt_struct.hpp>
#include <boost/spirit/home/x3.hpp>

#include <type_traits>

BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::Quantity, value, unit)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::PowerTail, signs, operand)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::Power, base, tail)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::Signed, signs, power)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::TermOp, op, operand)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::Term, first, rest)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::ExprOp, op, operand)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::Expr, first, rest)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::Call, function, args)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::SignalPoint, time, value)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::PointSignal, kind, points)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::TableSignal, file, column)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::KeyValue, key, value)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::ConstStmt, name, value)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::Range, lo, hi)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::ParamStmt, name, value, range, doc)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::NodeStmt, name, keys, doc)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::BoundaryStmt, name, keys, doc)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::ElementStmt, kind, name, nodes, keys, doc)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::InnerElement, kind, keys)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::CompositeStmt, mode, name, nodes, parts)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::Target, object, member)
BOOST_FUSION_ADAPT_STRUCT(thermnet::lang::ast::CaseAssign, target, value)

namespace thermnet::lang::grammar {

namespace x3 = boost::spirit::x3;
using x3::lexeme;
using x3::lit;

/// Context tag carrying the first byte of the file, so rules can record byte offsets.
struct buffer_tag;

/// Records the byte range of every Tagged node a rule produces.
struct annotate {
  template <typename Iterator, typename Attr, typename Context>
  void on_success(Iterator const& first, Iterator const& last, Attr& attr, Context const& ctx) {
    if constexpr (std::is_base_of_v<ast::Tagged, Attr>) {
      const char* base = x3::get<buffer_tag>(ctx);
      attr.begin = static_cast<std::uint32_t>(first - base);
      attr.end = static_cast<std::uint32_t>(last - base);
    }
  }
};

/// Unsigned reals without a trailing dot (so `1..10` is a range) and without nan/inf words.
template <typename T> struct number_policies : x3::ureal_policies<T> {
  static bool const allow_leading_dot = true;
  static bool const allow_trailing_dot = false;
  /// A '.' followed by another '.' is not a decimal point: `1..10` is a range.
  template <typename It> static bool parse_dot(It& first, It const& last) {
    if (first == last || *first != '.') return false;
    if (first + 1 != last && first[1] == '.') return false;
    ++first;
    return true;
  }
  template <typename It, typename Attr> static bool parse_nan(It&, It const&, Attr&) {
    return false;
  }
  template <typename It, typename Attr> static bool parse_inf(It&, It const&, Attr&) {
    return false;
  }
};
inline const x3::real_parser<double, number_policies<double>> unsigned_real{};

// Character classes as explicit byte sets: X3's x3::alpha, x3::alnum and x3::blank call the C
// classification functions, which must not see the negative chars of UTF-8 bytes (an assertion
// in debug builds, undefined behaviour otherwise). Identifiers are ASCII, so these are exact.
inline const auto alpha = x3::char_("a-zA-Z");
inline const auto alnum = x3::char_("a-zA-Z0-9");
inline const auto digit = x3::char_("0-9");
inline const auto blank = lit(' ') | lit('\t');

/// Matches a keyword only as a whole word (`node` but not `node2`).
inline auto kw(const char* word) {
  return lexeme[lit(word) >> !(alnum | lit('_'))];
}

// --- skippers -------------------------------------------------------------------------------
inline const auto comment = lexeme['#' >> *(x3::char_ - x3::eol)];
inline const auto continuation = lexeme['\\' >> *blank >> x3::eol];
/// Skips blanks, comments and line continuations; newlines stay significant.
inline const auto line_skipper = blank | lit('\r') | comment | continuation;
/// Separates the inner elements of a series/parallel block.
inline const auto block_separator = lit(';') | x3::eol;

// --- rule declarations ----------------------------------------------------------------------
struct identifier_class : annotate {};
struct string_class : annotate {};
struct unit_class : annotate {};
struct quantity_class : annotate {};
struct primary_class : annotate {};
struct call_class : annotate {};
struct paren_class : annotate {};
struct power_class : annotate {};
struct power_tail_class : annotate {};
struct term_op_class : annotate {};
struct expr_op_class : annotate {};
struct signed_class : annotate {};
struct term_class : annotate {};
struct expr_class : annotate {};
struct signal_kind_class : annotate {};
struct point_class : annotate {};
struct point_signal_class : annotate {};
struct table_signal_class : annotate {};
struct value_class : annotate {};
struct key_value_class : annotate {};
struct model_class : annotate {};
struct include_class : annotate {};
struct plugin_class : annotate {};
struct const_class : annotate {};
struct range_class : annotate {};
struct param_class : annotate {};
struct node_class : annotate {};
struct boundary_class : annotate {};
struct element_class : annotate {};
struct inner_class : annotate {};
struct composite_mode_class : annotate {};
struct composite_class : annotate {};
struct target_class : annotate {};
struct case_assign_class : annotate {};
struct case_data_class : annotate {};
struct case_item_class : annotate {};
struct case_header_class : annotate {};
struct statement_class : annotate {};
struct terminal_pair_class {};

inline const x3::rule<identifier_class, ast::Identifier> identifier = "name";
inline const x3::rule<terminal_pair_class, std::vector<ast::Identifier>> terminal_pair =
    "the two terminal nodes";
inline const x3::rule<string_class, ast::String> string_literal = "string";
inline const x3::rule<unit_class, ast::UnitText> unit = "unit in brackets";
inline const x3::rule<quantity_class, ast::Quantity> quantity = "number";
inline const x3::rule<primary_class, ast::Primary> primary = "operand";
inline const x3::rule<call_class, ast::Call> call = "function call";
inline const x3::rule<paren_class, ast::Expr> paren = "parenthesised expression";
inline const x3::rule<power_class, ast::Power> power = "operand";
inline const x3::rule<power_tail_class, ast::PowerTail> power_tail = "exponent";
inline const x3::rule<term_op_class, ast::TermOp> term_op = "operand";
inline const x3::rule<expr_op_class, ast::ExprOp> expr_op = "operand";
inline const x3::rule<signed_class, ast::Signed> signed_ = "operand";
inline const x3::rule<term_class, ast::Term> term = "operand";
inline const x3::rule<expr_class, ast::Expr> expr = "expression";
inline const x3::rule<signal_kind_class, ast::Identifier> signal_kind = "signal";
inline const x3::rule<point_class, ast::SignalPoint> signal_point = "'time: value' point";
inline const x3::rule<point_signal_class, ast::PointSignal> point_signal = "signal";
inline const x3::rule<table_signal_class, ast::TableSignal> table_signal = "table signal";
inline const x3::rule<value_class, ast::Value> value = "value";
inline const x3::rule<key_value_class, ast::KeyValue> key_value = "key = value";
inline const x3::rule<model_class, ast::ModelStmt> model_stmt = "model statement";
inline const x3::rule<include_class, ast::IncludeStmt> include_stmt = "include statement";
inline const x3::rule<plugin_class, ast::PluginStmt> plugin_stmt = "plugin statement";
inline const x3::rule<const_class, ast::ConstStmt> const_stmt = "const statement";
inline const x3::rule<range_class, ast::Range> range = "range 'LO .. HI'";
inline const x3::rule<param_class, ast::ParamStmt> param_stmt = "param statement";
inline const x3::rule<node_class, ast::NodeStmt> node_stmt = "node statement";
inline const x3::rule<boundary_class, ast::BoundaryStmt> boundary_stmt = "boundary statement";
inline const x3::rule<element_class, ast::ElementStmt> element_stmt = "element statement";
inline const x3::rule<inner_class, ast::InnerElement> inner_element =
    "inner element 'KIND key = value ...'";
inline const x3::rule<composite_mode_class, ast::Identifier> composite_mode = "series or parallel";
inline const x3::rule<composite_class, ast::CompositeStmt> composite_stmt = "series/parallel block";
inline const x3::rule<target_class, ast::Target> target = "case setting";
inline const x3::rule<case_assign_class, ast::CaseAssign> case_assign =
    "case setting 'name = value'";
inline const x3::rule<case_data_class, ast::CaseData> case_data = "data statement";
inline const x3::rule<case_item_class, ast::CaseItem> case_item = "case statement";
inline const x3::rule<case_header_class, ast::Identifier> case_header = "case header";
inline const x3::rule<statement_class, ast::Statement> statement = "statement";

// --- semantic actions for single-member nodes -------------------------------------------------
// X3 does not call on_success for rules whose right-hand side is a semantic action, and in Boost
// 1.74 _where() spans from the end of the match to the end of the input. So these actions take
// the node's byte range from a raw[] attribute; whole statements are tagged by the driver.
template <typename Ctx, typename Range> void tag(Ctx& ctx, Range const& r) {
  const char* base = x3::get<buffer_tag>(ctx);
  x3::_val(ctx).begin = static_cast<std::uint32_t>(r.begin() - base);
  x3::_val(ctx).end = static_cast<std::uint32_t>(r.end() - base);
}
inline const auto set_name = [](auto& ctx) {
  auto const& r = x3::_attr(ctx);
  x3::_val(ctx).name.assign(r.begin(), r.end());
  tag(ctx, r);
};
inline const auto set_raw_text = [](auto& ctx) {
  auto const& r = x3::_attr(ctx);
  x3::_val(ctx).text.assign(r.begin(), r.end());
  tag(ctx, r);
};
/// A string literal from its raw text: quotes removed, \" and \\ unescaped.
inline const auto set_string = [](auto& ctx) {
  auto const& r = x3::_attr(ctx);
  std::string& out = x3::_val(ctx).text;
  out.clear();
  for (auto it = r.begin() + 1; it + 1 < r.end(); ++it) {
    if (*it == '\\' && it + 2 < r.end()) ++it;
    out += *it;
  }
  tag(ctx, r);
};
inline const auto set_model_name = [](auto& ctx) { x3::_val(ctx).name = x3::_attr(ctx); };
inline const auto set_path = [](auto& ctx) { x3::_val(ctx).path = x3::_attr(ctx); };
inline const auto set_identifier = [](auto& ctx) { x3::_val(ctx) = x3::_attr(ctx); };

// --- lexical ----------------------------------------------------------------------------------
inline const auto identifier_def =
    x3::raw[lexeme[(alpha | x3::char_('_')) >> *(alnum | x3::char_('_'))]][set_name];
inline const auto escaped_char = lit('\\') >> x3::char_("\\\"");
inline const x3::rule<class string_body_class, std::string> string_body = "string";
inline const auto string_body_def = *(escaped_char | (x3::char_ - '"' - '\\' - x3::eol));
inline const auto string_literal_def = x3::raw[lexeme[('"' >> string_body) > '"']][set_string];
inline const auto unit_def =
    (lit('[') > x3::raw[lexeme[*(x3::char_ - ']' - '[' - x3::eol)]] > lit(']'))[set_raw_text];
/// A number not glued to letters or to a further '.' (so `3mm` and `1.2.3` are not numbers, while
/// `1..10` still is a range).
inline const auto number = lexeme[unsigned_real >> !(alnum | lit('_') | (lit('.') >> !lit('.')))];
inline const auto quantity_def = number >> -unit;

// --- expressions ------------------------------------------------------------------------------
inline const auto signs = *x3::char_("+-");
inline const auto paren_def = (lit('(') >> expr) > lit(')');
// Lists are `x >> *(',' > x)` rather than `x % ','`, so that a ',' not followed by an item is
// reported at the missing item; the list rules keep X3 from flattening them into their parent.
inline const x3::rule<class arg_list_class, std::vector<ast::Expr>> arg_list = "argument";
inline const auto arg_list_def = expr >> *(lit(',') > expr);
inline const auto call_def = (identifier >> lit('(') >> -arg_list) > lit(')');
inline const auto primary_def = quantity | call | identifier | paren;
inline const auto power_tail_def = signs >> primary;
inline const auto power_def = primary >> *(lit('^') > power_tail);
inline const auto signed__def = signs >> power;
inline const auto term_op_def = x3::char_("*/") > signed_;
inline const auto term_def = signed_ >> *term_op;
inline const auto expr_op_def = x3::char_("+-") > term;
inline const auto expr_def = term >> *expr_op;

// --- signals and values -----------------------------------------------------------------------
inline const auto signal_kind_def =
    x3::raw[lexeme[(lit("step") | lit("pwl")) >> !(alnum | lit('_'))]][set_name];
inline const auto signal_point_def = expr > lit(':') > expr;
inline const x3::rule<class point_list_class, std::vector<ast::SignalPoint>> point_list =
    "'time: value' point";
inline const auto point_list_def = signal_point >> *(lit(',') > signal_point);
inline const auto point_signal_def = (signal_kind >> lit('(') >> point_list) > lit(')');
inline const auto table_signal_def = (kw("table") >> lit('(') >> string_literal) >
                                     lit(',') > string_literal > lit(')');
inline const auto value_def = point_signal | table_signal | expr;
inline const auto key_value_def = identifier > lit('=') > value;

// --- statements -------------------------------------------------------------------------------
inline const auto model_stmt_def = (kw("model") > identifier)[set_model_name];
inline const auto include_stmt_def = (kw("include") > string_literal)[set_path];
inline const auto plugin_stmt_def = (kw("plugin") > string_literal)[set_path];
inline const auto const_stmt_def = kw("const") > identifier > lit('=') > expr;
inline const auto range_def = expr > lit("..") > expr;
inline const auto param_stmt_def = kw("param") > identifier > lit('=') > expr >
                                   -(kw("range") > range) > -string_literal;
inline const auto node_stmt_def = kw("node") > identifier > *key_value > -string_literal;
inline const auto boundary_stmt_def = kw("boundary") > identifier > *key_value > -string_literal;
/// A terminal node name: not a key (`k =`), and not a key whose '=' is missing (`G 2`).
inline const auto terminal = identifier >> !lit('=') >> !(digit | x3::char_("(+-."));
inline const auto element_stmt_def = identifier >>
                                     (identifier > *terminal > *key_value > -string_literal);
inline const auto inner_element_def = identifier > *key_value;
inline const auto composite_mode_def =
    x3::raw[lexeme[(lit("series") | lit("parallel")) >> !(alnum | lit('_'))]][set_name];
inline const auto terminal_pair_def = x3::repeat(2)[identifier];
inline const auto composite_stmt_def = composite_mode > identifier > terminal_pair > *x3::eol >
                                       lit('{') > *block_separator >
                                       *(inner_element >> *block_separator) > lit('}');
inline const auto statement_def = model_stmt | include_stmt | plugin_stmt | const_stmt |
                                  param_stmt | node_stmt | boundary_stmt | composite_stmt |
                                  element_stmt;

// --- cases ------------------------------------------------------------------------------------
// Extension: the '{' of a case or series/parallel block may also start the next line.
inline const auto case_header_def = (kw("case") > identifier > *x3::eol > lit('{'))[set_identifier];
inline const auto target_def = identifier >> -(lit('.') > identifier);
inline const auto case_assign_def = target > lit('=') > value;
// `data` is a keyword only when not followed by '=' or '.' (a param or node may be called data).
inline const auto case_data_def =
    ((kw("data") >> !(lit('=') | lit('.'))) > string_literal)[set_path];
inline const auto case_item_def = case_data | case_assign;

BOOST_SPIRIT_DEFINE(identifier, string_body, string_literal, unit, quantity, primary, arg_list,
                    call, paren, power, power_tail, term_op, expr_op, signed_, term, expr,
                    signal_kind, signal_point, point_list, point_signal, table_signal, value,
                    key_value, model_stmt, include_stmt, plugin_stmt, const_stmt, range, param_stmt,
                    node_stmt, boundary_stmt, element_stmt, inner_element, composite_mode,
                    terminal_pair, composite_stmt, statement, case_header, target, case_assign,
                    case_data, case_item)

} // namespace thermnet::lang::grammar
