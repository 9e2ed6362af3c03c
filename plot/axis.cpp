#include "plot/axis.hpp"

#include "plot/text.hpp"

#include <algorithm>

namespace thermnet::plot {

Axis linear_axis(double lo, double hi, Fit fit, int max_ticks, StepSet set) {
  pad_if_flat(lo, hi);
  Axis a;
  if (fit == Fit::extend) {
    const Ticks t = make_ticks(lo, hi, max_ticks, set);
    a.lo = t.values.front();
    a.hi = t.values.back();
    a.major = t.values;
    a.labels = tick_labels(t);
    return a;
  }
  // Ticks inside a kept range are fewer than around it: take the densest set that fits.
  const double span = hi - lo;
  for (int mt = max_ticks + 4;; --mt) {
    Ticks t = make_ticks(lo, hi, mt, set);
    double l = lo, h = hi;
    if (fit == Fit::snap) {
      if (t.values.front() >= lo - 0.05 * span) l = t.values.front();
      if (t.values.back() <= hi + 0.05 * span) h = t.values.back();
    }
    const double eps = t.step * 1e-9;
    std::erase_if(t.values, [&](double v) { return v < l - eps || v > h + eps; });
    if (static_cast<int>(t.values.size()) <= max_ticks || mt <= 2) {
      a.lo = l;
      a.hi = h;
      a.major = t.values;
      a.labels = tick_labels(t);
      return a;
    }
  }
}

Axis log_axis(double lo, double hi, Fit fit, int max_ticks) {
  Axis a;
  a.log = true;
  double l = std::log10(lo), h = std::log10(hi);
  if (!std::isfinite(l) || !std::isfinite(h)) {
    l = 0;
    h = 1;
  }
  if (l > h) std::swap(l, h);
  if (h - l < 1e-9) {
    l -= 0.5;
    h += 0.5;
  }
  const double fl = std::floor(l + 1e-9), ch = std::ceil(h - 1e-9);
  const double near = 0.1 * std::max(h - l, 1.0);
  if (fit == Fit::extend || (fit == Fit::snap && l - fl <= near)) l = fl;
  if (fit == Fit::extend || (fit == Fit::snap && ch - h <= near)) h = ch;
  a.lo = l;
  a.hi = h;
  const int first = static_cast<int>(std::ceil(l - 1e-9));
  const int last = static_cast<int>(std::floor(h + 1e-9));
  const int decades = last - first + 1;
  int stride = 1;
  for (const int s : {1, 2, 3, 5, 10, 20, 50, 100}) {
    stride = s;
    if ((decades + s - 1) / s <= std::max(max_ticks, 2)) break;
  }
  struct Tick {
    double t;
    std::string label;
  };
  std::vector<Tick> ticks;
  for (int k = first; k <= last; ++k) {
    if ((k - first) % stride != 0) continue;
    ticks.push_back({static_cast<double>(k), format_number(std::pow(10.0, k), 6)});
  }
  if (stride == 1 && h - l <= 8) {
    const bool label_2_5 = ticks.size() < 3;
    for (int k = static_cast<int>(std::floor(l)) - 1; k <= static_cast<int>(std::ceil(h)); ++k) {
      for (int m = 2; m <= 9; ++m) {
        const double t = k + std::log10(static_cast<double>(m));
        if (t < l - 1e-9 || t > h + 1e-9) continue;
        if (label_2_5 && (m == 2 || m == 5))
          ticks.push_back({t, format_number(m * std::pow(10.0, k), 6)});
        else
          a.minor.push_back(t);
      }
    }
  }
  std::sort(ticks.begin(), ticks.end(), [](const Tick& x, const Tick& y) { return x.t < y.t; });
  for (auto& t : ticks) {
    a.major.push_back(t.t);
    a.labels.push_back(std::move(t.label));
  }
  return a;
}

Axis make_axis(bool log, double dlo, double dhi,
               const std::optional<std::pair<double, double>>& fixed, double fixed_divisor, Fit fit,
               int max_ticks, StepSet set) {
  if (fixed) {
    double lo = fixed->first / fixed_divisor, hi = fixed->second / fixed_divisor;
    if (std::isfinite(lo) && std::isfinite(hi) && (!log || (lo > 0 && hi > 0)))
      return log ? log_axis(lo, hi, Fit::fixed, max_ticks)
                 : linear_axis(lo, hi, Fit::fixed, max_ticks, set);
  }
  return log ? log_axis(dlo, dhi, fit, max_ticks) : linear_axis(dlo, dhi, fit, max_ticks, set);
}

double max_label_width(const Axis& a, double font) {
  double w = 0;
  for (const auto& s : a.labels)
    w = std::max(w, text_width(s, font));
  return w;
}

double min_tick_gap(const Axis& a) {
  double gap = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < a.major.size(); ++i)
    gap = std::min(gap, std::fabs(a.pixel_t(a.major[i]) - a.pixel_t(a.major[i - 1])));
  return gap;
}

} // namespace thermnet::plot
