#pragma once
/// The Spirit X3 grammar of the netlist language: text -> position-tagged AST, every syntax error
/// reported.

#include "lang/ast.hpp"
#include "lang/diagnostics.hpp"
#include "lang/source.hpp"

namespace thermnet::lang {

/// Deepest bracket nesting accepted; deeper input is rejected before parsing so nothing overflows
/// the stack.
inline constexpr int max_nesting = 64;

/// Parses one file into statements; syntax errors are reported to `diags` and the parser resumes at
/// the next statement.
ast::File parse_file(FileId id, const SourceManager& sources, DiagnosticEngine& diags);

} // namespace thermnet::lang
