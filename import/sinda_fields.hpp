#pragma once
/// The lexical layer of SINDA/FLUINT input: comment lines (`C` in column 1), trailing `$`
/// comments, fields separated by commas or blanks, node references (`63` or `SUB.63`) and
/// Fortran numbers, each parsed with the place it stands for error messages.

#include "import/input_files.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace thermnet::importer::sinda {

/// One field of a data line.
struct Field {
  std::string_view text; ///< the field, trimmed
  lang::Span at;         ///< where it stands
};

/// True for a blank of SINDA input: space, tab, vertical tab, form feed or the DOS end-of-file
/// mark (0x1a).
bool blank(char c);

/// s without its leading and trailing blanks.
std::string_view trim(std::string_view s);

/// True for a comment line: `C` or `c` in column 1 followed by a blank or nothing.
bool is_comment_line(std::string_view line);

/// The line up to a trailing `$` comment, trailing blanks removed.
std::string_view strip_comment(std::string_view line);

/// The fields of a data line (after its `$` comment is removed): separated by commas, or by blanks
/// within a comma-separated part; an empty field between two commas is an error.
std::vector<Field> split_fields(const SourceLine& line);

/// A real value of a field, or an ImportError (`bad-number`) at the field.
double real_field(const Field& f);

/// An integer value of a field (a whole number; `1.0` is not one), or an ImportError.
std::int64_t integer_field(const Field& f, const char* what);

/// A node as conductor and source data name it.
struct NodeRef {
  std::string sub;     ///< submodel (upper case)
  std::int64_t id = 0; ///< node id (positive; a negative one marks a one-way conductor)
  lang::Span at;       ///< where it is named
};

/// A node reference: `SUB.ID` or a bare `ID` of `block_sub`; throws ImportError otherwise.
NodeRef node_field(const Field& f, const std::string& block_sub);

/// `text` in upper case (ASCII).
std::string upper(std::string_view text);

/// True when `name` can be a thermnet identifier (`[A-Za-z_][A-Za-z0-9_]*`).
bool is_identifier(std::string_view name);

} // namespace thermnet::importer::sinda
