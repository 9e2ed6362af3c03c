#pragma once
/// Values given on the command line: `--set NAME=VALUE` (a param) or `--set OBJECT.KEY=VALUE` (a
/// key of a node, boundary or element) on every command that runs a model, and the grids of
/// `thermnet sweep`. A value is a number in the unit the model file reads it in (SI; degC for a
/// temperature), or a number with a unit in brackets, e.g. `h_cp=0.02 [W/(cm^2*K)]`; a signal key
/// (P = pwl(...)) set this way becomes that constant.

#include "lang/model.hpp"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace CLI {
class App;
} // namespace CLI

namespace thermnet::app {

/// What a name on the command line denotes: a param, or a key of a node, boundary or element.
struct SetTarget {
  std::string name;                        ///< as written: PARAM or OBJECT.KEY
  std::string object;                      ///< node, boundary or element (empty for a param)
  std::string key;                         ///< its key (empty for a param)
  std::optional<lang::Dimension> dim;      ///< the unit dimension (none for a bare-number param)
  bool temperature = false;                ///< an absolute temperature: bare numbers are degC
  const lang::KeySchema* schema = nullptr; ///< a key's schema, for its valid range
  std::optional<std::pair<double, double>> range; ///< a ranged param's range, SI
};

/// Resolves `name` (a param, or OBJECT.KEY split at the last dot); throws lang::OverrideError
/// naming `option` for an unknown name (with a suggestion) or a key that cannot be set.
SetTarget resolve_target(const lang::Model& model, const std::string& name,
                         const std::string& option);

/// The SI value of `text` for `target`, checked against the key's valid range or the param's
/// range; throws lang::OverrideError naming `option`.
double target_value(const SetTarget& target, const std::string& text, const std::string& option);

/// `value` (SI) when `target` takes it: finite, within the key's valid range or the param's
/// range; throws lang::OverrideError naming `option`.
double checked_value(const SetTarget& target, double value, const std::string& option);

/// Adds `value` for `target` to `overrides` (`text` is the setting as written, for messages).
void add_override(lang::Overrides& overrides, const SetTarget& target, double value,
                  const std::string& text);

/// The values set by `--set` items; throws lang::OverrideError.
lang::Overrides parse_sets(const lang::Model& model, const std::vector<std::string>& sets);

/// Adds `target`'s name to `names`; throws lang::OverrideError naming `option` when it is there
/// already (a value given twice: which one would count?).
void refuse_repeated(std::vector<std::string>& names, const SetTarget& target,
                     const std::string& option);

/// Adds the repeatable `--set NAME=VALUE` option every command that runs a model takes, storing
/// its items in `sets`; `extra` is appended to its help text.
void add_set_option(CLI::App* cmd, std::vector<std::string>& sets, const std::string& extra = "");

/// Tells on stderr that the model file `out` written by `who` does not hold the model's `--set`
/// values (nothing when there are none).
void note_sets_not_written(const lang::Model& model, const std::string& who,
                           const std::string& out);

/// One swept param or key and its values (SI).
struct SweepAxis {
  std::string name;            ///< the param or OBJECT.KEY, as written
  std::vector<double> values;  ///< its values, SI
  double display_offset = 0.0; ///< subtracted for display (273.15 for a temperature, else 0)
  SetTarget target;            ///< what is swept
};

/// Parses `NAME=LO..HI:N` (N evenly spaced values, N >= 2) or `NAME=V1,V2,...`, NAME a param or
/// OBJECT.KEY; throws std::invalid_argument.
SweepAxis parse_sweep_axis(const lang::Model& model, const std::string& text);

} // namespace thermnet::app
