#include "app/option_rules.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <stdexcept>

namespace thermnet::app {
namespace {

/// Empty when `v` is finite and lies in [lo, hi]; else "a number from LO to HI".
std::string within(double v, double lo, double hi, const char* unit) {
  if (std::isfinite(v) && v >= lo && v <= hi) return {};
  return fmt::format("a number from {:g} to {:g}{}", lo, hi, unit);
}

bool whole(double v) {
  return std::isfinite(v) && v == std::floor(v);
}

} // namespace

std::string relative_tolerance_rule(double value) {
  return within(value, 1e-12, 1e-1, "");
}

std::string absolute_tolerance_rule(double value) {
  return within(value, 1e-12, 10.0, " K");
}

std::string positive_number_rule(double value) {
  return std::isfinite(value) && value > 0 ? std::string() : "a positive number";
}

std::string non_negative_number_rule(double value) {
  return std::isfinite(value) && value >= 0 ? std::string() : "a number from 0";
}

std::string positive_whole_rule(double value) {
  return whole(value) && value > 0 ? std::string() : "a positive whole number";
}

std::string at_least_two_whole_rule(double value) {
  return whole(value) && value >= 2 ? std::string() : "a whole number from 2";
}

std::string non_negative_whole_rule(double value) {
  return whole(value) && value >= 0 ? std::string() : "a non-negative whole number";
}

CLI::Validator rule_validator(NumberRule rule, const std::string& type_name) {
  return CLI::Validator(
      [rule](std::string& text) -> std::string {
        double v = 0;
        const char* b = text.data();
        const char* e = text.data() + text.size();
        const auto [p, ec] = std::from_chars(b, e, v);
        const std::string must = ec == std::errc() && p == e ? rule(v) : rule(std::nan(""));
        return must.empty() ? std::string() : fmt::format("'{}' is not {}", text, must);
      },
      type_name);
}

CLI::Validator output_file_validator() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        return text.empty() ? "an output needs a file name (got an empty one)" : std::string();
      },
      "FILE");
}

void require(NumberRule rule, double value, const std::string& name) {
  if (const std::string must = rule(value); !must.empty())
    throw std::invalid_argument(fmt::format("{} = {:g} is not {}", name, value, must));
}

} // namespace thermnet::app
