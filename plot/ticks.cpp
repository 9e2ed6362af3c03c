#include "plot/ticks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace thermnet::plot {
namespace {

// Removes trailing zeros of the fraction (and a bare '.'); "-0" becomes "0".
std::string trim_fraction(std::string s) {
  const std::size_t e = s.find_first_of("eE");
  std::string mant = s.substr(0, e);
  const std::string exp = e == std::string::npos ? std::string() : s.substr(e);
  if (mant.find('.') != std::string::npos) {
    while (!mant.empty() && mant.back() == '0')
      mant.pop_back();
    if (!mant.empty() && mant.back() == '.') mant.pop_back();
  }
  if (mant == "-0") mant = "0";
  return mant + exp;
}

// "1.5e6" style: mantissa with `decimals` decimals (trimmed), exponent without sign or zeros.
std::string exponent_form(double v, int decimals) {
  const std::string s = fmt::format("{:.{}e}", v, std::clamp(decimals, 0, 16));
  const std::size_t e = s.find('e');
  const std::string mant = trim_fraction(s.substr(0, e));
  const int exp = std::stoi(s.substr(e + 1));
  if (mant == "0") return "0";
  return exp == 0 ? mant : fmt::format("{}e{}", mant, exp);
}

std::string fixed_form(double v, int decimals) {
  return trim_fraction(fmt::format("{:.{}f}", v, std::clamp(decimals, 0, 17)));
}

double pow10i(int e) {
  return std::pow(10.0, e);
}

// k * 10^e, rounded once (so that 3 * 10^-1 is the double nearest 0.3).
double scaled(double k, int e) {
  return (e >= 0 ? k * pow10i(e) : k / pow10i(-e)) + 0.0;
}

} // namespace

void pad_if_flat(double& lo, double& hi) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) {
    lo = 0;
    hi = 1;
  }
  if (lo > hi) std::swap(lo, hi);
  const double mag = std::max(std::fabs(lo), std::fabs(hi));
  if (hi - lo <= mag * 1e-12) {
    const double c = 0.5 * (lo + hi);
    const double p = c != 0 ? std::fabs(c) * 0.05 : 1.0;
    lo = c - p;
    hi = c + p;
  }
}

Ticks make_ticks(double lo, double hi, int max_ticks, StepSet set) {
  lo = std::clamp(std::isfinite(lo) ? lo : 0.0, -1e300, 1e300);
  hi = std::clamp(std::isfinite(hi) ? hi : 1.0, -1e300, 1e300);
  pad_if_flat(lo, hi);
  max_ticks = std::max(max_ticks, 2);
  const double span = hi - lo;
  const int e0 = static_cast<int>(std::floor(std::log10(span / (max_ticks - 1)))) - 1;
  struct Step {
    double m; // step = m * 10^e
    int e;
    double value() const { return scaled(m, e); }
  };
  std::vector<Step> steps;
  for (int e = e0; e < e0 + 64; ++e)
    for (const double m : {1.0, 2.0, 5.0})
      steps.push_back({m, e});
  if (set != StepSet::decimal) {
    const double custom_end = set == StepSet::hours ? 1000 : 100;
    std::erase_if(steps, [&](const Step& s) { return s.value() >= 1 && s.value() < custom_end; });
    const std::vector<double> custom =
        set == StepSet::hours
            ? std::vector<double>{1, 2, 3, 6, 12, 24, 48, 72, 96, 168, 336, 504, 672}
            : std::vector<double>{1, 2, 5, 10, 15, 20, 30, 60};
    for (const double m : custom)
      steps.push_back({m, 0});
    std::stable_sort(steps.begin(), steps.end(),
                     [](const Step& x, const Step& y) { return x.value() < y.value(); });
  }
  // Round-off allowance, so that 0.3 counts as a multiple of 0.1.
  const double slack = 1e-9 * span + 1e-14 * std::max(std::fabs(lo), std::fabs(hi));
  for (const Step& s : steps) {
    const double step = s.value();
    if (!std::isfinite(step)) break;
    const double a = std::floor((lo + slack) / step);
    const double b = std::ceil((hi - slack) / step);
    if (b - a + 1 > max_ticks) continue;
    Ticks t;
    t.step = step;
    for (double k = a; k <= b; k += 1)
      t.values.push_back(scaled(k * s.m, s.e));
    return t;
  }
  // Two ticks cannot cover a range around a multiple of every step (e.g. -1..3): allow three.
  if (max_ticks < 3) return make_ticks(lo, hi, 3, set);
  return Ticks{{lo, hi}, hi - lo}; // not reached for finite input
}

TimeAxis choose_time_axis(double t_max_seconds) {
  if (!(t_max_seconds > 600)) return {"s", 1.0}; // also NaN and negative
  if (t_max_seconds <= 7200) return {"min", 60.0};
  return {"h", 3600.0};
}

Ticks nice_ticks(double lo, double hi, int max_ticks) {
  return make_ticks(lo, hi, max_ticks, StepSet::decimal);
}

std::vector<std::string> tick_labels(const Ticks& ticks) {
  std::vector<std::string> out;
  double max_abs = 0;
  for (const double v : ticks.values)
    max_abs = std::max(max_abs, std::fabs(v));
  const bool exp_mode = max_abs >= 1e6 || (max_abs > 0 && max_abs < 1e-3);
  const double step = ticks.step > 0 && std::isfinite(ticks.step) ? ticks.step : 1.0;
  const int step_exp = static_cast<int>(std::floor(std::log10(step) + 1e-9));
  for (const double v : ticks.values) {
    if (!std::isfinite(v)) {
      out.push_back(format_number(v));
    } else if (std::fabs(v) < step * 1e-6) {
      out.push_back("0");
    } else if (exp_mode) {
      const int ve = static_cast<int>(std::floor(std::log10(std::fabs(v)) + 1e-12));
      out.push_back(exponent_form(v, std::max(0, ve - step_exp)));
    } else {
      out.push_back(fixed_form(v, std::max(0, -step_exp)));
    }
  }
  return out;
}

std::string format_number(double value, int digits) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  if (value == 0) return "0";
  digits = std::clamp(digits, 1, 17);
  const double a = std::fabs(value);
  if (a >= 1e6 || a < 1e-3) return exponent_form(value, digits - 1);
  const int mag = static_cast<int>(std::floor(std::log10(a)));
  const std::string s = fixed_form(value, std::max(0, digits - 1 - mag));
  // Rounding may carry into a new digit (999999.7 -> "1000000"): switch to exponent form.
  return std::fabs(std::stod(s)) >= 1e6 ? exponent_form(value, digits - 1) : s;
}

} // namespace thermnet::plot
