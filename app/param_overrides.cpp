#include "app/param_overrides.hpp"

#include "lang/diagnostics.hpp"
#include "lang/units.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iostream>
#include <stdexcept>

namespace thermnet::app {

namespace {
using lang::kZeroCelsius;

std::pair<std::string, std::string> split_assignment(const std::string& text,
                                                     const std::string& option) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw lang::OverrideError(
        fmt::format("{}: '{}' is not NAME=VALUE (a param) or NAME.KEY=VALUE", option, text));
  return {text.substr(0, eq), text.substr(eq + 1)};
}

/// "param 'h'" or "P of heater 'h1'", for messages.
std::string describe(const SetTarget& t) {
  return t.object.empty() ? fmt::format("param '{}'", t.name)
                          : fmt::format("'{}' ('{}' of '{}')", t.name, t.key, t.object);
}

/// A value for messages: degC for a temperature, else SI with the dimension's unit.
std::string show(const SetTarget& t, double v) {
  if (t.temperature) return fmt::format("{:g} degC", v - kZeroCelsius);
  if (!t.dim || *t.dim == lang::dim::none) return fmt::format("{:g}", v);
  return fmt::format("{:g} {}", v, lang::describe(*t.dim));
}
} // namespace

SetTarget resolve_target(const lang::Model& model, const std::string& name,
                         const std::string& option) {
  SetTarget t;
  t.name = name;
  // Params first: a start temperature calibrated in a case is a param named NODE.T0@CASE.
  const auto params = model.params();
  for (const auto& p : params)
    if (p.name == name) {
      t.dim = p.dim;
      t.temperature = p.dim && *p.dim == lang::dim::temperature;
      if (p.ranged()) t.range = std::pair{*p.lo, *p.hi};
      return t;
    }
  const auto dot = name.rfind('.');
  if (dot != std::string::npos) {
    t.object = name.substr(0, dot);
    t.key = name.substr(dot + 1);
    if (t.object.empty() || t.key.empty())
      throw lang::OverrideError(
          fmt::format("{}: '{}' is neither a param nor NAME.KEY", option, name));
    const lang::KeySchema& ks = model.settable_key(t.object, t.key, option);
    t.dim = ks.dim;
    t.temperature = ks.absolute_temperature;
    t.schema = &ks;
    return t;
  }
  std::vector<std::string> names;
  for (const auto& p : params)
    names.push_back(p.name);
  std::string msg = fmt::format("{}: the model has no param '{}'", option, name);
  if (auto s = lang::closest_match(name, names))
    msg += fmt::format("; did you mean '{}'?", *s);
  else
    msg += " (a key of a node, boundary or element is set as NAME.KEY=VALUE)";
  throw lang::OverrideError(msg);
}

double target_value(const SetTarget& t, const std::string& text, const std::string& option) {
  std::size_t used = 0;
  double x = 0.0;
  try {
    x = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || !std::isfinite(x))
    throw lang::OverrideError(fmt::format(
        "{}: '{}' for {} is not a number{}", option, text, describe(t),
        t.schema && t.schema->type == lang::KeyType::signal ? " (a signal key is set to a constant)"
                                                            : ""));
  std::string rest = text.substr(used);
  const auto first = rest.find_first_not_of(' ');
  rest = first == std::string::npos ? "" : rest.substr(first);
  double v = t.temperature ? x + kZeroCelsius : x;
  if (!rest.empty()) {
    // A letter after the number is most likely a unit; anything else (2*3, 1e3/4) an expression,
    // which the command line does not evaluate.
    if (!std::isalpha(static_cast<unsigned char>(rest.front())) && rest.front() != '[')
      throw lang::OverrideError(fmt::format(
          "{}: '{}' is not a number: a value here is a number, optionally with a unit in "
          "brackets (5 [mm]); expressions are not evaluated",
          option, text));
    if (rest.front() != '[' || rest.back() != ']')
      throw lang::OverrideError(
          fmt::format("{}: '{}': write a unit in brackets, e.g. 5 [mm]", option, text));
    lang::Unit u;
    try {
      u = lang::parse_unit(rest.substr(1, rest.size() - 2));
    } catch (const lang::UnitError& e) {
      throw lang::OverrideError(fmt::format("{}: '{}': {}", option, text, e.what()));
    }
    if (t.dim && !(u.dim == *t.dim))
      throw lang::OverrideError(fmt::format("{}: '{}': {} is in {}, not {}", option, text,
                                            describe(t), lang::describe(*t.dim),
                                            lang::describe(u.dim)));
    v = u.scale * x + u.offset;
  }
  return checked_value(t, v, option);
}

double checked_value(const SetTarget& t, double v, const std::string& option) {
  if (!std::isfinite(v))
    throw lang::OverrideError(fmt::format("{}: {} must be a finite number", option, describe(t)));
  if (t.schema && !t.schema->accepts(v))
    throw lang::OverrideError(fmt::format(
        "{}: {} must be {}, not {}", option, describe(t),
        t.temperature ? "above absolute zero (-273.15 degC)" : t.schema->range_text(), show(t, v)));
  if (t.range && (v < t.range->first || v > t.range->second))
    throw lang::OverrideError(fmt::format("{}: {} = {} lies outside its range {} .. {}", option,
                                          describe(t), show(t, v), show(t, t.range->first),
                                          show(t, t.range->second)));
  return v;
}

void add_override(lang::Overrides& overrides, const SetTarget& t, double value,
                  const std::string& text) {
  if (t.object.empty()) {
    overrides.params.insert_or_assign(t.name, value);
    overrides.param_texts.push_back(text);
    return;
  }
  overrides.keys.push_back({t.object, t.key, value, text});
}

lang::Overrides parse_sets(const lang::Model& model, const std::vector<std::string>& sets) {
  lang::Overrides overrides;
  std::vector<std::string> names;
  for (const auto& s : sets) {
    const auto [name, text] = split_assignment(s, "--set");
    const std::string option = "--set " + s;
    const SetTarget t = resolve_target(model, name, "--set");
    refuse_repeated(names, t, option);
    add_override(overrides, t, target_value(t, text, "--set"), option);
  }
  return overrides;
}

void refuse_repeated(std::vector<std::string>& names, const SetTarget& target,
                     const std::string& option) {
  if (std::find(names.begin(), names.end(), target.name) != names.end())
    throw lang::OverrideError(
        fmt::format("{}: {} is given more than once", option, describe(target)));
  names.push_back(target.name);
}

void add_set_option(CLI::App* cmd, std::vector<std::string>& sets, const std::string& extra) {
  cmd->add_option("--set", sets,
                  "a value for this run (repeatable): a param NAME=VALUE or a key of a node, "
                  "boundary or element NAME.KEY=VALUE (e.g. h1.P=3.5, tstat.on=16); a number in "
                  "the model's units (SI, degC for a temperature) or with a unit in brackets, "
                  "e.g. 'h=0.02 [W/(cm^2*K)]'; over the model's and the case's values" +
                      extra)
      ->type_name("NAME=VALUE");
}

void note_sets_not_written(const lang::Model& model, const std::string& who,
                           const std::string& out) {
  const lang::Overrides& o = model.overrides();
  if (o.empty()) return;
  std::vector<std::string> given = o.param_texts;
  for (const auto& k : o.keys)
    given.push_back(k.option);
  std::cerr << fmt::format("{}: note: {} keeps the model's own values, not those of {}; give "
                           "them again when you run it\n",
                           who, out, fmt::join(given, ", "));
}

SweepAxis parse_sweep_axis(const lang::Model& model, const std::string& text) {
  const auto [name, spec] = split_assignment(text, "--param");
  SweepAxis axis{name, {}, 0.0, resolve_target(model, name, "--param")};
  const SetTarget& t = axis.target;
  if (t.temperature) axis.display_offset = kZeroCelsius;
  const auto dots = spec.find("..");
  if (dots == std::string::npos) {
    std::size_t start = 0;
    for (;;) {
      const auto comma = spec.find(',', start);
      axis.values.push_back(target_value(t, spec.substr(start, comma - start), "--param"));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    return axis;
  }
  const auto colon = spec.find(':', dots);
  if (colon == std::string::npos)
    throw std::invalid_argument(
        fmt::format("--param: '{}': write LO..HI:N (N values) or a list V1,V2,...", text));
  const double lo = target_value(t, spec.substr(0, dots), "--param");
  const double hi = target_value(t, spec.substr(dots + 2, colon - dots - 2), "--param");
  std::size_t used = 0;
  long n = 0;
  try {
    n = std::stol(spec.substr(colon + 1), &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != spec.size() - colon - 1 || n < 2 || n > 100000)
    throw std::invalid_argument(
        fmt::format("--param: '{}': N after ':' must be a whole number from 2 to 100000", text));
  for (long k = 0; k < n; ++k)
    axis.values.push_back(lo + (hi - lo) * static_cast<double>(k) / static_cast<double>(n - 1));
  return axis;
}

} // namespace thermnet::app
