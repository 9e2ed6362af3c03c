#include "cli/model_rewrite.hpp"

#include "lang/units.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <optional>

namespace thermnet::cli {

namespace {

constexpr double kZeroCelsius = 273.15;

/// How a value expression was written.
struct Written {
  bool literal = false;            ///< a lone (signed) number, with or without a unit
  std::optional<std::string> unit; ///< the unit text between the brackets
};

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

Written classify(std::string_view s) {
  Written w;
  std::size_t i = 0;
  const auto skip = [&] {
    while (i < s.size() && is_space(s[i]))
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
  while (j < s.size() && is_space(s[j]))
    ++j;
  if (j != s.size()) return w;
  w.literal = true;
  w.unit = std::string(s.substr(i + 1, close - i - 1));
  return w;
}

std::string number(double v) {
  return fmt::format("{:.8g}", v);
}

} // namespace

std::string format_param_value(std::string_view written, const lang::ParamInfo& param, double si) {
  const Written w = classify(written);
  const bool temperature = param.dim && *param.dim == lang::dim::temperature;
  if (w.literal && w.unit) {
    try {
      const lang::Unit u = lang::parse_unit(*w.unit);
      return fmt::format("{} [{}]", number((si - u.offset) / u.scale), *w.unit);
    } catch (const lang::UnitError&) {
      // Not expected for a checked model; fall through to the SI form.
    }
  } else if (w.literal) {
    return number(temperature ? si - kZeroCelsius : si);
  }
  if (!param.dim || param.dim->dimensionless()) return number(si);
  return fmt::format("{} [{}]", number(si), lang::describe(*param.dim));
}

RewriteResult rewrite_params(const lang::SourceManager& sources, lang::FileId root,
                             const std::vector<ParamUpdate>& updates) {
  RewriteResult r;
  r.text = sources.text(root);
  std::vector<const ParamUpdate*> here;
  for (const auto& u : updates) {
    if (u.param.value_span.file == root)
      here.push_back(&u);
    else
      r.skipped.push_back(u.param.name);
  }
  // From the end of the file backwards, so earlier spans keep their offsets.
  std::sort(here.begin(), here.end(), [](const ParamUpdate* a, const ParamUpdate* b) {
    return a->param.value_span.begin > b->param.value_span.begin;
  });
  for (const ParamUpdate* u : here) {
    const lang::Span s = u->param.value_span;
    if (s.end < s.begin || s.end > r.text.size()) continue;
    const std::string_view old(r.text.data() + s.begin, s.end - s.begin);
    r.text.replace(s.begin, s.end - s.begin, format_param_value(old, u->param, u->value));
  }
  return r;
}

} // namespace thermnet::cli
