#pragma once
/// Param values given on the command line: `--set NAME=VALUE` and the grids of `thermnet sweep`.
/// A value is a number in the param's declared unit system (SI; degC for a temperature), or a
/// number with a unit in brackets, e.g. `h_cp=0.02 [W/(cm^2*K)]`.

#include "lang/model.hpp"

#include <string>
#include <vector>

namespace thermnet::cli {

/// The SI value of `text` for param `p` (see above); throws std::invalid_argument naming `option`.
double param_value(const lang::ParamInfo& p, const std::string& text, const std::string& option);

/// The params of `model` set by `--set NAME=VALUE` items; throws std::invalid_argument for an
/// unknown name (with a suggestion) or a bad value.
lang::ParamValues parse_param_sets(const lang::Model& model, const std::vector<std::string>& sets);

/// One swept param and its values (SI).
struct SweepAxis {
  std::string name;            ///< the param
  std::vector<double> values;  ///< its values, SI
  double display_offset = 0.0; ///< subtracted for display (273.15 for a temperature, else 0)
};

/// Parses `NAME=LO..HI:N` (N evenly spaced values, N >= 2) or `NAME=V1,V2,...`; throws
/// std::invalid_argument.
SweepAxis parse_sweep_axis(const lang::Model& model, const std::string& text);

} // namespace thermnet::cli
