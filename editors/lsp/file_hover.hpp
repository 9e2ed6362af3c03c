#pragma once
/// Hover texts of what a model says about the files it reads (a `table(...)`, a case's `data`
/// statement), from the model's text alone: a model is untrusted input, so these never open the
/// files or quote them.

#include "lang/model.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace thermnet::lsp {

/// A hover's markdown and the bytes of the document it describes.
struct SpanText {
  std::string markdown;  ///< the text shown
  std::size_t begin = 0; ///< first byte of what it describes
  std::size_t end = 0;   ///< one past its last byte
};

/// The innermost `table(...)` of file `file` around byte `at`: its file (or the case's data file,
/// with the file each case names), column, interpolation, time column, separator and unit.
std::optional<SpanText> table_hover(const lang::Model& m, lang::FileId file, std::size_t at);

/// The case `data` statement of file `file` (whose text is `text`) around byte `at`: its file, time
/// column, separator, unit and which series it compares with which columns. Nothing on the target
/// of a column map (`air` in `air = t2` is the node's).
std::optional<SpanText> data_statement_hover(const lang::Model& m, lang::FileId file,
                                             std::size_t at, std::string_view text);

} // namespace thermnet::lsp
