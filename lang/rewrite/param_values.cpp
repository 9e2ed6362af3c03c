#include "lang/rewrite/param_values.hpp"

#include "lang/units.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <optional>

namespace thermnet::rewrite {

namespace {

/// How a value expression was written.
struct Written {
  bool literal = false;            ///< a lone (signed) number, with or without a unit
  std::optional<std::string> unit; ///< the unit text between the brackets
};

Written classify(std::string_view s) {
  Written w;
  std::size_t i = 0;
  const auto skip = [&] {
    while (i < s.size() && is_blank(s[i]))
      ++i;
  };
  skip();
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  skip();
  double v = 0;
  auto [p, ec] = std::from_chars(s.data() + i, s.data() + s.size(), v);
  if (ec != std::errc()) return w;
  i = static_cast<std::size_t>(p - s.data());
  skip();
  if (i == s.size()) {
    w.literal = true;
    return w;
  }
  if (s[i] != '[') return w;
  const std::size_t close = s.find(']', i);
  if (close == std::string_view::npos) return w;
  std::size_t j = close + 1;
  while (j < s.size() && is_blank(s[j]))
    ++j;
  if (j != s.size()) return w;
  w.literal = true;
  w.unit = std::string(s.substr(i + 1, close - i - 1));
  return w;
}

/// The distinct unit texts (between square brackets) of an expression, in order.
std::vector<std::string> units_in(std::string_view s) {
  std::vector<std::string> units;
  for (std::size_t open = s.find('['); open != std::string_view::npos; open = s.find('[', open)) {
    const std::size_t close = s.find(']', open);
    if (close == std::string_view::npos) break;
    std::string u(s.substr(open + 1, close - open - 1));
    u.erase(std::remove_if(u.begin(), u.end(), is_blank), u.end());
    if (std::find(units.begin(), units.end(), u) == units.end()) units.push_back(u);
    open = close;
  }
  return units;
}

std::string number(double v) {
  return fmt::format("{:.8g}", v);
}

/// `si` written in the unit `unit` when that unit parses and has the param's dimension.
std::optional<std::string> in_unit(const std::string& unit, const lang::ParamInfo& param,
                                   double si) {
  try {
    const lang::Unit u = lang::parse_unit(unit);
    if (!param.dim || u.dim != *param.dim) return std::nullopt;
    return fmt::format("{} [{}]", number((si - u.offset) / u.scale), unit);
  } catch (const lang::UnitError&) {
    return std::nullopt; // not expected for a checked model
  }
}

} // namespace

std::string format_param_value(std::string_view written, const lang::ParamInfo& param, double si) {
  const Written w = classify(written);
  const bool temperature = param.dim && *param.dim == lang::dim::temperature;
  if (w.literal && w.unit) {
    if (auto s = in_unit(*w.unit, param, si)) return *s;
  } else if (w.literal) {
    return number(temperature ? si - lang::kZeroCelsius : si);
  } else {
    const auto units = units_in(written);
    if (units.size() == 1)
      if (auto s = in_unit(units.front(), param, si)) return *s;
  }
  if (!param.dim || param.dim->dimensionless()) return number(si);
  return fmt::format("{} [{}]", number(si), lang::describe(*param.dim));
}

std::vector<TextEdit> param_edits(const lang::SourceManager& sources, lang::FileId file,
                                  const std::vector<ParamUpdate>& updates) {
  const std::string& text = sources.text(file);
  std::vector<TextEdit> edits;
  for (const auto& u : updates) {
    const lang::Span s = u.param.value_span;
    if (s.file != file || s.end < s.begin || s.end > text.size()) continue;
    const std::string_view old(text.data() + s.begin, s.end - s.begin);
    edits.push_back({s.begin, s.end, format_param_value(old, u.param, u.value)});
  }
  return edits;
}

RewriteResult rewrite_params(const lang::SourceManager& sources, lang::FileId root,
                             const std::vector<ParamUpdate>& updates) {
  RewriteResult r;
  r.text = apply_edits(sources.text(root), param_edits(sources, root, updates));
  for (const auto& u : updates)
    if (u.param.value_span.file != root) r.skipped.push_back(u.param.name);
  return r;
}

} // namespace thermnet::rewrite
