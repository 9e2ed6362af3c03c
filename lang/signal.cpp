#include "lang/signal.hpp"

#include "lang/time_program.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace thermnet::lang {

namespace {
const std::vector<double> no_corners;
}

Signal& Signal::operator=(const Signal& other) {
  constant = other.constant;
  shape_ = other.shape_;
  hint_.store(0, std::memory_order_relaxed);
  return *this;
}

Signal& Signal::operator=(Signal&& other) noexcept {
  constant = other.constant;
  shape_ = std::move(other.shape_);
  hint_.store(0, std::memory_order_relaxed);
  return *this;
}

const std::vector<double>& Signal::times() const {
  return shape_ ? shape_->t : no_corners;
}

const std::vector<double>& Signal::values() const {
  return shape_ ? shape_->v : no_corners;
}

Signal::Shape& Signal::shape() {
  if (!shape_)
    shape_ = new Shape();
  else if (shape_->use_count() > 1) // shared with copies: this signal's own from now on
    shape_ = new Shape(*shape_);
  return *shape_;
}

Signal::Shape& Signal::shape(Kind kind) {
  Shape& s = shape();
  s.kind = kind;
  return s;
}

double Signal::at(double time) const {
  const Kind kind = this->kind();
  if (kind == Kind::expression) return shape_->program->at(time) * shape_->scale + shape_->offset;
  const std::vector<double>& t = times();
  const std::vector<double>& v = values();
  if (kind == Kind::constant || t.empty()) return t.empty() ? constant : v.front();
  if (time <= t.front()) return v.front();
  if (time >= t.back()) return v.back();
  // First corner strictly after `time`; the segment is [k-1, k). Tried first: the last reading's
  // segment and the next one (a run reads its inputs forward in time).
  std::size_t k = hint_.load(std::memory_order_relaxed);
  if (k > 0 && k < t.size() && t[k - 1] <= time && time < t[k]) {
  } else if (k + 1 < t.size() && k > 0 && t[k] <= time && time < t[k + 1]) {
    ++k;
  } else {
    k = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), time) - t.begin());
  }
  hint_.store(k, std::memory_order_relaxed);
  if (kind == Kind::step) return v[k - 1];
  double w = (time - t[k - 1]) / (t[k] - t[k - 1]);
  return v[k - 1] + w * (v[k] - v[k - 1]);
}

bool Signal::piecewise_linear() const {
  return kind() != Kind::expression || shape_->program->piecewise_linear();
}

std::string Signal::text() const {
  switch (kind()) {
  case Kind::constant:
    return fmt::format("{:.17g}", constant);
  case Kind::expression: {
    std::string out = shape_->program->text();
    if (shape_->scale != 1.0) out = fmt::format("({:.17g} * {})", shape_->scale, out);
    if (shape_->offset != 0.0) out = fmt::format("({} + {:.17g})", out, shape_->offset);
    return out;
  }
  case Kind::step:
  case Kind::pwl:
    break;
  }
  std::string out = kind() == Kind::step ? "step(" : "pwl(";
  for (std::size_t i = 0; i < shape_->t.size(); ++i)
    out += fmt::format("{}{:.17g}: {:.17g}", i ? ", " : "", shape_->t[i], shape_->v[i]);
  return out + ")";
}

bool Signal::same_as(const Signal& other) const {
  if (kind() != other.kind()) return false;
  if (is_constant()) return constant == other.constant;
  const Shape& a = *shape_;
  const Shape& b = *other.shape_;
  if (kind() != Kind::expression) return a.t == b.t && a.v == b.v;
  return a.scale == b.scale && a.offset == b.offset &&
         (a.program == b.program || a.program->text() == b.program->text());
}

Signal Signal::scaled(double factor) const {
  Signal s = *this;
  s.constant *= factor;
  if (s.shape_) {
    Shape& own = s.shape();
    for (auto& x : own.v)
      x *= factor;
    own.scale *= factor;
    own.offset *= factor;
  }
  return s;
}

} // namespace thermnet::lang
