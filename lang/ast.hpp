#pragma once
/// The position-tagged syntax tree built by the grammar; it carries no meaning (see sema.hpp for
/// that).
///
/// Chains of operators are flat lists (as in Spirit X3's calc examples) so that neither parsing,
/// evaluation nor destruction recurses deeper than the bracket nesting, which the parser bounds.

#include <boost/spirit/home/x3/support/ast/variant.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace thermnet::lang::ast {

namespace x3 = boost::spirit::x3;

/// Byte range [begin, end) of a node inside its file, filled in by the parser.
struct Tagged {
  std::uint32_t begin = 0; ///< first byte
  std::uint32_t end = 0;   ///< one past the last byte
};

/// A name as written, e.g. a node, param or key.
struct Identifier : Tagged {
  std::string name; ///< the identifier text
};

/// A string literal (quotes removed, escapes resolved).
struct String : Tagged {
  std::string text; ///< contents
};

/// The text between square brackets after a number, e.g. "W/(m*K)".
struct UnitText : Tagged {
  std::string text; ///< unit text as written
};

/// A number with an optional unit: `160 [W/(m*K)]`.
struct Quantity : Tagged {
  double value = 0;             ///< the number as written
  std::optional<UnitText> unit; ///< the unit, if any
};

struct Call;
struct Expr;

/// An operand: a quantity, a function call, a name, or a parenthesised expression.
struct Primary : x3::variant<Quantity, x3::forward_ast<Call>, Identifier, x3::forward_ast<Expr>> {
  using base_type::base_type;
  using base_type::operator=;
};

/// `base ^ e1 ^ e2 ...` (right-associative); each exponent may carry leading signs.
struct PowerTail {
  std::string signs; ///< leading '+'/'-' of the exponent
  Primary operand;   ///< the exponent
};
/// A primary raised to a chain of powers.
struct Power : Tagged {
  Primary base;                ///< the base
  std::vector<PowerTail> tail; ///< exponents, applied right to left
};
/// A power with leading unary signs, e.g. `--x^2` = -(-(x^2)).
struct Signed : Tagged {
  std::string signs; ///< leading '+'/'-' characters
  Power power;       ///< the operand
};
/// One `* operand` or `/ operand` step of a term.
struct TermOp {
  char op = '*';  ///< '*' or '/'
  Signed operand; ///< right-hand side
};
/// A product/quotient chain.
struct Term : Tagged {
  Signed first;             ///< first factor
  std::vector<TermOp> rest; ///< further factors, left to right
};
/// One `+ term` or `- term` step of an expression.
struct ExprOp {
  char op = '+'; ///< '+' or '-'
  Term operand;  ///< right-hand side
};
/// A sum/difference chain: the root of every expression.
struct Expr : Tagged {
  Term first;               ///< first term
  std::vector<ExprOp> rest; ///< further terms, left to right
};
/// A function call `name(arg, ...)`.
struct Call : Tagged {
  Identifier function;    ///< function name
  std::vector<Expr> args; ///< arguments
};

/// One `time: value` point of a step or pwl signal.
struct SignalPoint : Tagged {
  Expr time;  ///< time (seconds unless a unit is given)
  Expr value; ///< value from that time on
};
/// `step(...)` or `pwl(...)`.
struct PointSignal : Tagged {
  Identifier kind;                 ///< "step" or "pwl"
  std::vector<SignalPoint> points; ///< the points in order
};
/// `table("file.csv", "column")`.
struct TableSignal : Tagged {
  String file;   ///< CSV path relative to the model file
  String column; ///< column name
};

/// What may follow `=` where a signal is allowed: a signal or a plain expression.
struct Value : x3::variant<PointSignal, TableSignal, Expr> {
  using base_type::base_type;
  using base_type::operator=;
};

/// `key = value`.
struct KeyValue : Tagged {
  Identifier key; ///< the key
  Value value;    ///< its value
};

/// `model NAME`.
struct ModelStmt : Tagged {
  Identifier name; ///< model name
};
/// `include "file"`.
struct IncludeStmt : Tagged {
  String path; ///< path relative to the including file
};
/// `plugin "lib.so"` (extension: loads a plugin library).
struct PluginStmt : Tagged {
  String path; ///< path relative to the model file
};
/// `const NAME = EXPR`.
struct ConstStmt : Tagged {
  Identifier name; ///< the constant
  Expr value;      ///< its value
};
/// `LO .. HI` of a param.
struct Range : Tagged {
  Expr lo; ///< lower bound
  Expr hi; ///< upper bound
};
/// `param NAME = EXPR [range LO .. HI] ["description"]`.
struct ParamStmt : Tagged {
  Identifier name;            ///< the param
  Expr value;                 ///< its value
  std::optional<Range> range; ///< calibration range
  std::optional<String> doc;  ///< description
};
/// `node NAME key = ...` (C, T0).
struct NodeStmt : Tagged {
  Identifier name;            ///< the node
  std::vector<KeyValue> keys; ///< C = ..., T0 = ...
  std::optional<String> doc;  ///< description
};
/// `boundary NAME T = VALUE`.
struct BoundaryStmt : Tagged {
  Identifier name;            ///< the boundary
  std::vector<KeyValue> keys; ///< T = ...
  std::optional<String> doc;  ///< description
};
/// `KIND NAME NODE... key = value ...` — an element of a plugin kind.
struct ElementStmt : Tagged {
  Identifier kind;               ///< element kind (resolved by the registry)
  Identifier name;               ///< element name
  std::vector<Identifier> nodes; ///< terminal nodes
  std::vector<KeyValue> keys;    ///< key = value pairs
  std::optional<String> doc;     ///< description
};
/// One inner element of a series/parallel block: `KIND key = value ...`.
struct InnerElement : Tagged {
  Identifier kind;            ///< element kind
  std::vector<KeyValue> keys; ///< its keys
};
/// `series|parallel NAME A B { ... ; ... }`.
struct CompositeStmt : Tagged {
  Identifier mode;                 ///< "series" or "parallel"
  Identifier name;                 ///< element name
  std::vector<Identifier> nodes;   ///< the two terminals
  std::vector<InnerElement> parts; ///< inner elements
};
/// A dotted target inside a case: `film.P`, `ambient.T`, `h_gap`, `duration`.
struct Target : Tagged {
  Identifier object;                ///< element, boundary, param, or case key
  std::optional<Identifier> member; ///< key after the dot, if any
};
/// `target = value` inside a case.
struct CaseAssign : Tagged {
  Target target; ///< what is set
  Value value;   ///< to what
};
/// `data "file.csv"` inside a case.
struct CaseData : Tagged {
  String path; ///< CSV path relative to the model file
};
/// One statement inside a case block.
struct CaseItem : x3::variant<CaseData, CaseAssign> {
  using base_type::base_type;
  using base_type::operator=;
};
/// `case NAME { ... }`.
struct CaseStmt : Tagged {
  Identifier name;             ///< case name
  std::vector<CaseItem> items; ///< its statements
};

/// Any top-level statement.
struct Statement : x3::variant<ModelStmt, IncludeStmt, PluginStmt, ConstStmt, ParamStmt, NodeStmt,
                               BoundaryStmt, CompositeStmt, CaseStmt, ElementStmt> {
  using base_type::base_type;
  using base_type::operator=;
};

/// The first two words of a top-level statement that failed to parse (`node b C 1` -> node, b),
/// so that later references to the name it meant to declare are not reported as unknown.
struct Unparsed : Tagged {
  Identifier head; ///< first word: a keyword or an element kind
  Identifier name; ///< second word: the name being declared (may be empty)
};

/// The statements of one file, in order.
struct File {
  std::uint32_t file_id = 0;         ///< SourceManager id
  std::vector<Statement> statements; ///< parsed statements (those with syntax errors are skipped)
  std::vector<Unparsed> unparsed;    ///< statements skipped because of a syntax error
  std::size_t syntax_errors = 0;     ///< number of syntax errors reported for this file
};

} // namespace thermnet::lang::ast
