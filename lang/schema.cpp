#include "lang/schema.hpp"

#include <fmt/format.h>

#include <cmath>

namespace thermnet::lang {

std::string KeySchema::range_text() const {
  // Stored in K (> 0) but written in degC: say what the limit is in the user's unit.
  if (absolute_temperature && min && *min == 0.0 && !max)
    return "above absolute zero (> -273.15 degC)";
  if (min && max)
    return fmt::format("in {}{:g}, {:g}{}", min_exclusive ? '(' : '[', *min, *max,
                       max_exclusive ? ')' : ']');
  if (min) return fmt::format("{} {:g}", min_exclusive ? ">" : ">=", *min);
  if (max) return fmt::format("{} {:g}", max_exclusive ? "<" : "<=", *max);
  return {};
}

bool KeySchema::accepts(double v) const {
  if (min && (min_exclusive ? !(v > *min) : !(v >= *min))) return false;
  if (max && (max_exclusive ? !(v < *max) : !(v <= *max))) return false;
  return true;
}

bool unresolved_lag(double lag, std::optional<double> duration) {
  if (!(lag > 0.0)) return false;
  if (!std::isfinite(1.0 / lag)) return true;
  return duration && lag < 1e-7 * *duration;
}

const KeySchema* ElementSchema::key(std::string_view name) const {
  for (const auto& k : keys)
    if (k.name == name) return &k;
  return nullptr;
}

std::vector<std::string> ElementSchema::key_names() const {
  std::vector<std::string> names;
  names.reserve(keys.size());
  for (const auto& k : keys)
    names.push_back(k.name);
  return names;
}

} // namespace thermnet::lang
