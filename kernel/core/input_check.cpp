#include "kernel/core/input_check.hpp"

#include "lang/evaluator.hpp"
#include "lang/model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace thermnet {

InputCheck::InputCheck(const lang::NetworkSpec& spec) {
  for (std::size_t n = 0; n < spec.nodes.size(); ++n)
    if (spec.nodes[n].boundary && spec.nodes[n].T.kind() == lang::Signal::Kind::expression)
      inputs_.push_back({static_cast<int>(n), -1, nullptr});
  for (std::size_t e = 0; e < spec.elements.size(); ++e) {
    const auto& el = spec.elements[e];
    if (!el.schema) continue;
    for (const auto& [name, value] : el.values)
      if (value.kind() == lang::Signal::Kind::expression)
        inputs_.push_back({-1, static_cast<int>(e), el.schema->key(name)});
  }
}

void InputCheck::at(const lang::NetworkSpec& spec, double t) const {
  for (const Input& in : inputs_) {
    const lang::NodeSpec* node =
        in.node >= 0 ? &spec.nodes[static_cast<std::size_t>(in.node)] : nullptr;
    const lang::ElementSpec* el =
        node ? nullptr : &spec.elements[static_cast<std::size_t>(in.element)];
    const lang::Signal& signal = node ? node->T : el->values.at(in.key->name);
    const double v = signal.at(t);
    // The expression's own place (a case's override is written in the case), else the statement.
    const lang::Signal::Shape* shape = signal.shape_if();
    const bool located = shape && shape->mark.end > shape->mark.begin;
    const lang::Span where = located ? shape->mark : node ? node->where : el->where;
    const lang::Span start = located ? shape->at : lang::Span{where.file, where.begin, where.begin};
    const auto what = [&] {
      return node ? fmt::format("T of boundary '{}'", node->name)
                  : fmt::format("{} of {} '{}'", in.key->name, el->kind(), el->name);
    };
    if (!std::isfinite(v))
      throw lang::ModelError(lang::DiagnosticEngine::make(lang::DiagId::input_not_finite, start,
                                                          where, what(), fmt::format("{:g}", t),
                                                          fmt::format("{}", v)));
    const bool temperature = !in.key || in.key->absolute_temperature;
    const bool ok = in.key ? in.key->accepts(v) : v > 0.0;
    if (ok) continue;
    const std::string range =
        temperature ? "above absolute zero (-273.15 degC)" : in.key->range_text();
    throw lang::ModelError(lang::DiagnosticEngine::make(
        lang::DiagId::input_out_of_range, start, where, what(), range,
        !in.key       ? lang::format_value(v, lang::dim::temperature, true)
        : temperature ? lang::format_outside(v, *in.key, lang::dim::temperature, true)
                      : lang::format_outside(v, *in.key, in.key->dim),
        fmt::format("{:g}", t)));
  }
}

void InputCheck::unbounded_near(const lang::NetworkSpec& spec, double t, double t0) const {
  for (const Input& in : inputs_) {
    const lang::NodeSpec* node =
        in.node >= 0 ? &spec.nodes[static_cast<std::size_t>(in.node)] : nullptr;
    const lang::ElementSpec* el =
        node ? nullptr : &spec.elements[static_cast<std::size_t>(in.element)];
    const lang::Signal& signal = node ? node->T : el->values.at(in.key->name);
    if (!(t > t0)) continue;
    // Its largest magnitude within 1e-7 of t (relative, both sides), a little farther (1e-4 ..
    // 1e-3), and over the run before. A pole grows by orders of magnitude as t is approached
    // (tan, 1/x); a jump (a step inside the expression) or a steep but smooth rise does not.
    const auto magnitude = [&signal](double at, double& into) {
      const double v = signal.at(at);
      if (!std::isnan(v)) into = std::max(into, std::abs(v)); // (NaN: the run's check names it)
    };
    const double scale = std::max(1.0, std::abs(t));
    double close = 0.0, farther = 0.0, before = 0.0;
    magnitude(t, close);
    for (double d : {1e-9, 1e-8, 1e-7}) {
      magnitude(t - d * scale, close);
      magnitude(t + d * scale, close);
    }
    for (double d : {1e-4, 1e-3}) {
      magnitude(t - d * scale, farther);
      magnitude(t + d * scale, farther);
    }
    constexpr int samples = 64;
    const double end = t0 + 0.98 * (t - t0);
    for (int k = 0; k <= samples; ++k)
      magnitude(t0 + (end - t0) * k / samples, before);
    const bool pole = !std::isfinite(close) || (close > 100.0 * farther &&
                                                close > 1e6 * std::max({before, farther, 1e-300}));
    if (!pole) continue;
    const lang::Signal::Shape* shape = signal.shape_if();
    const bool located = shape && shape->mark.end > shape->mark.begin;
    const lang::Span where = located ? shape->mark : node ? node->where : el->where;
    const lang::Span start = located ? shape->at : lang::Span{where.file, where.begin, where.begin};
    const std::string what = node
                                 ? fmt::format("T of boundary '{}'", node->name)
                                 : fmt::format("{} of {} '{}'", in.key->name, el->kind(), el->name);
    const lang::Dimension dim = in.key ? in.key->dim : lang::dim::temperature;
    throw lang::ModelError(lang::DiagnosticEngine::make(
        lang::DiagId::input_unbounded, start, where, what, fmt::format("{:.10g}", t),
        lang::format_value(close, dim), lang::format_value(before, dim)));
  }
}

} // namespace thermnet
