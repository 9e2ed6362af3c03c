#pragma once
/// Rewriting param values in a model file in place (calibrate -o, diagnose --write): only the
/// bytes of each value expression change; comments, layout and everything else stay
/// byte-identical.

#include "lang/model.hpp"

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace thermnet::cli {

/// A param and its new value (SI, as ParamInfo::value).
struct ParamUpdate {
  lang::ParamInfo param; ///< the param (value_span locates its expression)
  double value = 0.0;    ///< new value, SI
};

/// A replacement of the bytes [begin, end) of one file's text.
struct TextEdit {
  std::uint32_t begin = 0; ///< first byte replaced
  std::uint32_t end = 0;   ///< one past the last byte replaced
  std::string text;        ///< the new bytes
};

/// The rewritten root file and the params that could not be written there.
struct RewriteResult {
  std::string text;                 ///< the root file's new text
  std::vector<std::string> skipped; ///< params declared in other (included) files, untouched
};

/// The new value expression of a param, in the unit its current expression was written in: a
/// lone `NUMBER [UNIT]` keeps UNIT (degC/degF converted with their offset), a bare number stays
/// bare (a bare param of temperature dimension is written in degC, as bare temperatures are); an
/// expression becomes a number in the one unit it is written with (`2 * 1.25 [W/(m*K)]` ->
/// `2.5 [W/(m*K)]`), a bare number if it has no unit and no dimension, else the SI value with its
/// SI unit.
std::string format_param_value(std::string_view written, const lang::ParamInfo& param, double si);

/// The edits that replace the value expression of each param declared in file `file`.
std::vector<TextEdit> param_edits(const lang::SourceManager& sources, lang::FileId file,
                                  const std::vector<ParamUpdate>& updates);

/// Applies non-overlapping edits (in any order) to a text.
std::string apply_edits(std::string text, std::vector<TextEdit> edits);

/// The edits that insert each named case's lines (one per line, each indented and followed by
/// `comment`) just before the closing brace of its block (replacing the blanks before it) in file
/// `file`; the names of the cases whose block is not in that file (or unknown) go to `elsewhere`.
std::vector<TextEdit> case_block_edits(const lang::Model& model, lang::FileId file,
                                       const std::map<std::string, std::string>& lines,
                                       const std::string& comment,
                                       std::vector<std::string>& elsewhere);

/// Replaces the value expression of each param declared in file `root` by its new value
/// (format_param_value); params declared in other files are listed in `skipped`.
RewriteResult rewrite_params(const lang::SourceManager& sources, lang::FileId root,
                             const std::vector<ParamUpdate>& updates);

} // namespace thermnet::cli
