#pragma once
/// The position-tagged syntax tree built by the parser; it carries no meaning (the model loader
/// and the elaborator give it one).
///
/// The tree is built once and never copied (its nodes are move-only). Names are views into the
/// file's text, which the SourceManager keeps in place; expressions are stored flat, one array of
/// nodes per file, so a deep expression needs no recursion to destroy; the lists of a node,
/// element or series/parallel statement (terminals, keys, inner elements) sit in per-file blocks
/// (Chunks) the statement views, so such a statement allocates nothing of its own. A generated
/// netlist line thus costs its Statement (120 bytes), a KeyValue (56) per key, a Ref (40) per
/// terminal and an ExprNode (24) per literal.

#include <algorithm>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace thermnet::lang::ast {

/// Index into one of a File's arrays.
using Index = std::uint32_t;
/// No index.
inline constexpr Index none = ~Index{0};

/// Storage of the per-statement lists of a File (an element's terminals and keys, a node's keys):
/// each list is one contiguous run in a block that never moves once written, so the statements
/// hold a span into it, the File may be moved, and an ordinary statement costs no allocation of
/// its own. Blocks grow from a few items to 64 KiB, so a small file stays small.
template <typename T> class Chunks {
public:
  /// No storage yet.
  Chunks() = default;
  /// Takes the blocks over (they stay where they are, so the spans into them stay valid).
  Chunks(Chunks&&) = default;
  /// Takes the blocks over.
  Chunks& operator=(Chunks&&) = default;
  Chunks(const Chunks&) = delete; // a copy's statements would view the original's blocks
  Chunks& operator=(const Chunks&) = delete;

  /// Moves `items` into the storage as one run and clears them; the run (empty: no storage).
  std::span<const T> append(std::vector<T>& items) {
    if (items.empty()) return {};
    if (blocks_.empty() || blocks_.back().capacity() - blocks_.back().size() < items.size()) {
      next_ = std::min(next_ * 2, max_block);
      blocks_.emplace_back().reserve(std::max(next_, items.size()));
    }
    std::vector<T>& block = blocks_.back(); // reserved: pushing never reallocates it
    const std::size_t first = block.size();
    for (T& item : items)
      block.push_back(std::move(item));
    items.clear();
    return {block.data() + first, block.size() - first};
  }

private:
  static constexpr std::size_t max_block = std::max<std::size_t>(1, 65536 / sizeof(T));
  std::vector<std::vector<T>> blocks_; // each filled up to the capacity it was reserved with
  std::size_t next_ = 4;               // items in the next block, doubling up to max_block
};

/// Byte range [begin, end) of a node inside its file, filled in by the parser.
struct Tagged {
  std::uint32_t begin = 0; ///< first byte
  std::uint32_t end = 0;   ///< one past the last byte
};

/// A name as written, e.g. a node, param or key; `name` views the file's text.
struct Identifier : Tagged {
  std::string_view name; ///< the identifier text
};

/// A string literal (quotes removed, escapes resolved).
struct String : Tagged {
  std::string text; ///< contents
};

/// The text between square brackets after a number, e.g. "W/(m*K)" (its span excludes the
/// brackets).
struct UnitText : Tagged {
  std::string text; ///< unit text as written (newlines inside brackets read as blanks)
};

/// One node of an expression, stored in File::exprs (24 bytes: a literal's value shares its
/// place with the second operand, which a literal does not have).
struct ExprNode : Tagged {
  /// What the node computes.
  enum class Op : std::uint8_t {
    number,   ///< `value`
    quantity, ///< `value [unit]`: a = index in File::units
    name,     ///< a = index in File::names
    call,     ///< a = index in File::names (the function); File::args[b] = n, then n roots
    negate,   ///< -a
    add,      ///< a + b
    subtract, ///< a - b
    multiply, ///< a * b
    divide,   ///< a / b
    power,    ///< a ^ b (the span of every power in a chain `x ^ y ^ z` is the whole chain)
    group,    ///< (a): its value must be finite (the span includes the parentheses)
    signal,   ///< a step, pwl or table signal: a = index in File::signals
    ref,      ///< another object's key (`film.P`, `room.T`): a = index in File::expr_refs
  };
  Index a = none;     ///< first operand or table index
  Op op = Op::number; ///< the operation
  union {
    double value = 0; ///< number and quantity literal (signs folded into one with a unit)
    Index b;          ///< second operand or table index (an operation or a call)
  };
};

/// An expression: the root of its nodes in File::exprs, and its span.
struct Expr : Tagged {
  Index root = none; ///< root node
  /// True when the expression is present.
  bool valid() const { return root != none; }
};

/// One item of an index list: `i + 1`, or a range `1 .. 10` (in a declaration).
struct IndexItem : Tagged {
  Expr lo;                ///< the index, or the first of a range
  std::optional<Expr> hi; ///< the last of a range
};

struct Ref;
/// The parts of a reference after its first name: its index list and further `.name[...]` parts.
struct RefTail {
  std::vector<IndexItem> index; ///< `[ ... ]` after the first name (empty: none)
  std::vector<Ref> rest;        ///< `.part` after it, each a plain or indexed name
};

/// A name with optional index list and dotted parts: `p`, `p[i + 1]`, `u[2].panel[3, 4]`, `film.P`.
struct Ref : Tagged {
  Identifier id;                 ///< the first name
  std::unique_ptr<RefTail> tail; ///< index list and further parts (null for a plain name)

  /// True for a plain name (no index, no dots).
  bool plain() const { return !tail; }
  /// The index list of the first name (empty when none).
  const std::vector<IndexItem>& index() const;
  /// The dotted parts after the first (empty when none).
  const std::vector<Ref>& rest() const;
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
/// `time = "column" [unit]`: which column of a CSV file holds the time, and its unit or format
/// (`[min]`, `[h]`, `[unix s]`, `[unix ns]`, `[iso]`; seconds when left out).
struct TimeOption : Tagged {
  String column;                ///< the column's name
  std::optional<UnitText> unit; ///< its unit or format
};
/// How a CSV file is laid out, where a `table` or `data` statement says so (extension).
struct FileOptions {
  std::optional<TimeOption> time;  ///< the time column (default: `time`, seconds)
  std::optional<String> separator; ///< the field separator (default: `,`)
  std::vector<Tagged> misplaced;   ///< options given twice, or `hold` in a data statement
};
/// `table("file.csv", "column" [, hold] [, before = VALUE] [, time = ...] [, separator = ...])
/// [unit]`, or
/// `table(data, "column", ...)` for a column of the case's data file.
struct TableSignal : Tagged {
  String file;                  ///< CSV path relative to the model file (empty for `data`)
  bool case_data = false;       ///< `table(data, ...)`: the case's data file
  String column;                ///< column name
  bool hold = false;            ///< zero-order hold instead of linear interpolation
  std::optional<Expr> before;   ///< `before = VALUE`: the value before the first row
  FileOptions options;          ///< the file's layout, when not the default
  std::optional<UnitText> unit; ///< unit of the column's values (bare when left out)
};
/// A signal standing in an expression (ExprNode::signal).
struct SignalExpr : std::variant<PointSignal, TableSignal> {
  using variant::variant;
  /// Its byte range.
  const Tagged& tag() const {
    return std::visit([](const auto& s) -> const Tagged& { return s; }, *this);
  }
};

/// What may follow `=` where a value is allowed: an expression (which may hold signals), or a
/// reference with an index or dots standing alone (`sense = p[3]`, `P = film.P`).
struct Value {
  Expr expr;                ///< the expression, when `ref` is null
  std::unique_ptr<Ref> ref; ///< a lone reference, else null

  /// The expression, or nullptr for a lone reference.
  const Expr* as_expr() const { return ref ? nullptr : &expr; }
  /// The lone reference, or nullptr.
  const Ref* as_reference() const { return ref.get(); }
  /// The byte range of whichever form the value has.
  Tagged span() const;
};

/// `key = value`.
struct KeyValue : Tagged {
  Identifier key; ///< the key
  Value value;    ///< its value
};
/// The keys of a statement, a run in File::key_lists.
using KeyList = std::span<const KeyValue>;
/// The terminals of a statement, a run in File::ref_lists.
using RefList = std::span<const Ref>;

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
/// `param NAME = EXPR [range LO .. HI] ["description"]`; inside a submodel the value may be left
/// out (the instance must then give it).
struct ParamStmt : Tagged {
  Identifier name;             ///< the param
  Expr value;                  ///< its value (invalid when left out)
  std::optional<Range> range;  ///< calibration range
  std::unique_ptr<String> doc; ///< description
};
/// `node NAME key = ...` (C, T0) or `boundary NAME T = VALUE`; the name may carry an index list.
struct NodeStmt : Tagged {
  bool boundary = false;       ///< boundary (true) or node
  Ref name;                    ///< the node or boundary
  KeyList keys;                ///< C = ..., T0 = ... or T = ... (in File::key_lists)
  std::unique_ptr<String> doc; ///< description
};
/// `KIND NAME NODE... key = value ...`: an element of a plugin kind, or an instance of a submodel.
struct ElementStmt : Tagged {
  Identifier kind;             ///< element kind or submodel (resolved by the model loader)
  Ref name;                    ///< element name
  bool mean = false;           ///< the terminals are written `mean(a, b, ...)` (a sensor)
  RefList nodes;               ///< terminal nodes (in File::ref_lists)
  KeyList keys;                ///< key = value pairs (in File::key_lists)
  std::unique_ptr<String> doc; ///< description
};
/// One inner element of a series/parallel block: `KIND key = value ...`.
struct InnerElement : Tagged {
  Identifier kind; ///< element kind
  KeyList keys;    ///< its keys (in File::key_lists)
};
/// `series|parallel NAME A B { ... ; ... }`.
struct CompositeStmt : Tagged {
  Identifier mode;                     ///< "series" or "parallel"
  Ref name;                            ///< element name
  RefList nodes;                       ///< the two terminals (in File::ref_lists)
  std::span<const InnerElement> parts; ///< inner elements (in File::part_lists)
};

/// `VAR in LO .. HI`: one loop variable of a `for` header.
struct LoopRange : Tagged {
  Identifier var; ///< the loop variable
  Expr lo;        ///< first value
  Expr hi;        ///< last value (inclusive)
};

struct Statement;
/// `for VAR in LO .. HI [, VAR in LO .. HI] { statements }` (extension).
struct ForStmt : Tagged {
  std::vector<LoopRange> ranges; ///< the loop variables, outermost first
  std::vector<Statement> body;   ///< the statements repeated
};
/// `submodel NAME(TERMINAL, ...) { statements }` (extension).
struct SubmodelStmt : Tagged {
  Identifier name;                   ///< the submodel, used like an element kind
  std::vector<Identifier> terminals; ///< its terminal nodes, in order
  std::vector<Statement> body;       ///< its declarations
};

/// A setting inside a case: `film.P`, `u1.pcb.T0`, `h_gap`, `duration` (the last part is the
/// key when there are several).
struct Target : Tagged {
  Ref path; ///< the dotted name as written
};
/// `target = value [, expr ...]` inside a case (a list only for `output`).
struct CaseAssign : Tagged {
  Target target;                ///< what is set
  Value value;                  ///< to what
  std::vector<Expr> more;       ///< further items of a list `output = 0, 100, 250`
  std::unique_ptr<Range> range; ///< `w.T0 = 20 range 15 .. 30`: calibrated per case (extension)
};
/// One column named in a data statement's column map, with its weight in a mean.
struct ColumnSource : Tagged {
  String column;              ///< the column's name (a name or a string as written)
  std::optional<Expr> weight; ///< `column: weight` in a weighted mean
};
/// `TARGET = column [unit]` or `TARGET = mean(a, b, ...) [unit]` in a data statement's block: the
/// node, boundary or sensor a measured series is compared with, and where it is read.
struct ColumnMap : Tagged {
  Ref target;                        ///< node, boundary or sensor
  bool mean = false;                 ///< the (weighted) mean of several columns
  std::vector<ColumnSource> sources; ///< the columns (one unless a mean)
  std::optional<UnitText> unit;      ///< temperature unit of these columns
};
/// `data "file.csv" [unit] [time = ...] [separator = ...] [{ TARGET = COLUMN ... }]` inside a
/// case.
struct CaseData : Tagged {
  String path;                    ///< CSV path relative to the model file
  std::optional<UnitText> unit;   ///< the temperature unit of the file's values (extension)
  FileOptions options;            ///< the file's layout, when not the default (extension)
  bool mapped = false;            ///< a column map was given: only its columns are compared
  std::vector<ColumnMap> columns; ///< the column map (extension)
};
struct CaseItem;
/// `for VAR in LO .. HI { settings }` inside a case (extension).
struct CaseFor : Tagged {
  std::vector<LoopRange> ranges; ///< the loop variables, outermost first
  std::vector<CaseItem> items;   ///< the settings repeated
};
/// One statement inside a case block.
struct CaseItem : std::variant<CaseData, CaseAssign, CaseFor> {
  using variant::variant;
};
/// `case NAME { ... }`.
struct CaseStmt : Tagged {
  Identifier name;             ///< case name
  std::vector<CaseItem> items; ///< its statements
  /// Its settings skipped for a syntax error (`data`, `duration`): what they would have set is
  /// not missing, so nothing more is said about it.
  bool unparsed_data = false, unparsed_duration = false;
};

/// `require KIND "GROUP"... LIMIT [from TIME] [in CASE, ...] ["description"]` (extension): a
/// requirement a run must meet. KIND is band (LIMIT `LO .. HI`), gradient, power or energy
/// (`max EXPR`) or margin (`min EXPR`); each group is a node or element name or a glob.
struct RequireStmt : Tagged {
  Identifier kind;               ///< band, gradient, power, energy or margin
  std::vector<String> groups;    ///< one or two name patterns, as written
  std::optional<Expr> lo;        ///< band: the lower limit
  Expr limit;                    ///< band: the upper limit; else the `max`/`min` value
  Identifier bound;              ///< `max` or `min` (empty for a band)
  std::optional<Expr> from;      ///< `from TIME`: checked from then on
  std::vector<Identifier> cases; ///< `in CASE, ...`: only in these cases (empty: all)
  std::unique_ptr<String> doc;   ///< description
};

/// A rare statement kept on the heap, so that it does not set the size of every statement (a
/// `require` is 160 bytes; a node or element statement, of which a netlist has one per line, 80
/// or 112). Made from the statement the parser built.
template <typename T> struct Boxed {
  std::unique_ptr<T> stmt; ///< the statement (never null)
  /// Moves a parsed statement to the heap.
  Boxed(T&& s) : stmt(std::make_unique<T>(std::move(s))) {}
  /// The statement.
  const T& operator*() const { return *stmt; }
  /// The statement's members.
  const T* operator->() const { return stmt.get(); }
};
/// A statement held in place (the counterpart of the next overload).
template <typename T> T& unboxed(T& s) {
  return s;
}
/// A statement held in a box.
template <typename T> T& unboxed(Boxed<T>& s) {
  return *s.stmt;
}
/// A statement held in a box.
template <typename T> const T& unboxed(const Boxed<T>& s) {
  return *s.stmt;
}

/// Any statement.
struct Statement
    : std::variant<ModelStmt, IncludeStmt, PluginStmt, ConstStmt, ParamStmt, NodeStmt, ElementStmt,
                   CompositeStmt, CaseStmt, ForStmt, SubmodelStmt, Boxed<RequireStmt>> {
  using variant::variant;
};

/// The byte range of any statement.
const Tagged& tag_of(const Statement& s);

/// The first two words of a statement that failed to parse (`node b C 1` -> node, b), so that
/// later references to the name it meant to declare are not reported as unknown.
struct Unparsed : Tagged {
  Identifier head; ///< first word: a keyword or an element kind
  Identifier name; ///< second word: the name being declared (may be empty)
};

/// The statements of one file, in order, with the tables their expressions refer to.
struct File {
  std::uint32_t file_id = 0;         ///< SourceManager id
  std::vector<Statement> statements; ///< parsed statements (those with syntax errors skipped)
  std::vector<Unparsed> unparsed;    ///< statements skipped because of a syntax error
  std::size_t syntax_errors = 0;     ///< number of syntax errors reported for this file
  std::vector<ExprNode> exprs;       ///< every expression node of the file
  std::vector<Identifier> names;     ///< names used in expressions (ExprNode::name, call)
  std::vector<UnitText> units;       ///< units of quantity literals
  std::vector<Index> args;           ///< roots of call arguments (ExprNode::call)
  std::vector<SignalExpr> signals;   ///< signals standing in expressions (ExprNode::signal)
  std::vector<Ref> expr_refs;        ///< references to keys in expressions (ExprNode::ref)
  Chunks<Ref> ref_lists;             ///< terminals of element and series/parallel statements
  Chunks<KeyValue> key_lists;        ///< keys of node, element and inner element statements
  Chunks<InnerElement> part_lists;   ///< inner elements of series/parallel statements

  /// The node at an index.
  const ExprNode& node(Index i) const { return exprs[i]; }
  /// The roots of a call's argument expressions.
  std::span<const Index> call_args(const ExprNode& call) const {
    return {args.data() + call.b + 1, args[call.b]};
  }
};

} // namespace thermnet::lang::ast
