#include "lang/signal.hpp"

#include "lang/time_program.hpp"

#include <algorithm>

namespace thermnet::lang {

double Signal::at(double time) const {
  if (kind == Kind::expression) return program->at(time) * scale + offset;
  if (kind == Kind::constant || t.empty()) return t.empty() ? constant : v.front();
  if (time <= t.front()) return v.front();
  if (time >= t.back()) return v.back();
  // First corner strictly after `time`; the segment is [k-1, k).
  auto it = std::upper_bound(t.begin(), t.end(), time);
  auto k = static_cast<std::size_t>(it - t.begin());
  if (kind == Kind::step) return v[k - 1];
  double w = (time - t[k - 1]) / (t[k] - t[k - 1]);
  return v[k - 1] + w * (v[k] - v[k - 1]);
}

Signal Signal::scaled(double factor) const {
  Signal s = *this;
  s.constant *= factor;
  for (auto& x : s.v)
    x *= factor;
  s.scale *= factor;
  s.offset *= factor;
  return s;
}

} // namespace thermnet::lang
