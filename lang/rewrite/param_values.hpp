#pragma once
/// Rewriting param values in a model file in place (calibrate -o, diagnose --write): only the
/// bytes of each value expression change; comments, layout and everything else stay
/// byte-identical.

#include "lang/model.hpp"
#include "lang/rewrite/text_edit.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace thermnet::rewrite {

/// A param and its new value (SI, as ParamInfo::value).
struct ParamUpdate {
  lang::ParamInfo param; ///< the param (value_span locates its expression)
  double value = 0.0;    ///< new value, SI
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

/// Replaces the value expression of each param declared in file `root` by its new value
/// (format_param_value); params declared in other files are listed in `skipped`.
RewriteResult rewrite_params(const lang::SourceManager& sources, lang::FileId root,
                             const std::vector<ParamUpdate>& updates);

} // namespace thermnet::rewrite
