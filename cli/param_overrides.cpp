#include "cli/param_overrides.hpp"

#include "lang/diagnostics.hpp"
#include "lang/units.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace thermnet::cli {

namespace {
constexpr double kZeroCelsius = 273.15;

bool is_temperature(const lang::ParamInfo& p) {
  return p.dim && *p.dim == lang::dim::temperature;
}

const lang::ParamInfo& find_param(const std::vector<lang::ParamInfo>& params,
                                  const std::string& name, const std::string& option) {
  for (const auto& p : params)
    if (p.name == name) return p;
  std::vector<std::string> names;
  for (const auto& p : params)
    names.push_back(p.name);
  std::string msg = fmt::format("{}: the model has no param '{}'", option, name);
  if (auto s = lang::closest_match(name, names)) msg += fmt::format("; did you mean '{}'?", *s);
  throw std::invalid_argument(msg);
}

std::pair<std::string, std::string> split_assignment(const std::string& text,
                                                     const std::string& option) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw std::invalid_argument(fmt::format("{}: '{}' is not NAME=VALUE", option, text));
  return {text.substr(0, eq), text.substr(eq + 1)};
}
} // namespace

double param_value(const lang::ParamInfo& p, const std::string& text, const std::string& option) {
  std::size_t used = 0;
  double x = 0.0;
  try {
    x = std::stod(text, &used);
  } catch (const std::exception&) {
    throw std::invalid_argument(
        fmt::format("{}: '{}' for param '{}' is not a number", option, text, p.name));
  }
  std::string rest = text.substr(used);
  const auto first = rest.find_first_not_of(' ');
  rest = first == std::string::npos ? "" : rest.substr(first);
  if (rest.empty()) return is_temperature(p) ? x + kZeroCelsius : x;
  if (rest.front() != '[' || rest.back() != ']')
    throw std::invalid_argument(
        fmt::format("{}: '{}': write a unit in brackets, e.g. 5 [mm]", option, text));
  lang::Unit u;
  try {
    u = lang::parse_unit(rest.substr(1, rest.size() - 2));
  } catch (const lang::UnitError& e) {
    throw std::invalid_argument(fmt::format("{}: '{}': {}", option, text, e.what()));
  }
  if (p.dim && !(u.dim == *p.dim))
    throw std::invalid_argument(fmt::format("{}: '{}': param '{}' is in {}, not {}", option, text,
                                            p.name, lang::describe(*p.dim), lang::describe(u.dim)));
  return u.scale * x + u.offset;
}

lang::ParamValues parse_param_sets(const lang::Model& model, const std::vector<std::string>& sets) {
  lang::ParamValues values;
  if (sets.empty()) return values;
  const auto params = model.params();
  for (const auto& s : sets) {
    const auto [name, text] = split_assignment(s, "--set");
    values.insert_or_assign(name, param_value(find_param(params, name, "--set"), text, "--set"));
  }
  return values;
}

SweepAxis parse_sweep_axis(const lang::Model& model, const std::string& text) {
  const auto [name, spec] = split_assignment(text, "--param");
  const auto params = model.params();
  const lang::ParamInfo& p = find_param(params, name, "--param");
  SweepAxis axis{name, {}, is_temperature(p) ? kZeroCelsius : 0.0};
  const auto dots = spec.find("..");
  if (dots == std::string::npos) {
    std::size_t start = 0;
    for (;;) {
      const auto comma = spec.find(',', start);
      axis.values.push_back(param_value(p, spec.substr(start, comma - start), "--param"));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    return axis;
  }
  const auto colon = spec.find(':', dots);
  if (colon == std::string::npos)
    throw std::invalid_argument(
        fmt::format("--param: '{}': write LO..HI:N (N values) or a list V1,V2,...", text));
  const double lo = param_value(p, spec.substr(0, dots), "--param");
  const double hi = param_value(p, spec.substr(dots + 2, colon - dots - 2), "--param");
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

} // namespace thermnet::cli
