#pragma once
/// Rewriting param values in a model file in place (calibrate -o): only the bytes of each value
/// expression change; comments, layout and everything else stay byte-identical.

#include "lang/model.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace thermnet::cli {

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
/// bare (a bare param of temperature dimension is written in degC, as bare temperatures are), any
/// other expression is replaced by the SI value with its SI unit.
std::string format_param_value(std::string_view written, const lang::ParamInfo& param, double si);

/// Replaces the value expression of each param declared in file `root` by its new value
/// (format_param_value); params declared in other files are listed in `skipped`.
RewriteResult rewrite_params(const lang::SourceManager& sources, lang::FileId root,
                             const std::vector<ParamUpdate>& updates);

} // namespace thermnet::cli
