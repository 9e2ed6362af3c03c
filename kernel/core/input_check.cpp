#include "kernel/core/input_check.hpp"

#include "lang/evaluator.hpp"
#include "lang/model.hpp"

#include <fmt/format.h>

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
    const double v = node ? node->T.at(t) : el->values.at(in.key->name).at(t);
    const lang::Span where = node ? node->where : el->where;
    const lang::Span start{where.file, where.begin, where.begin};
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
        temperature ? lang::format_value(v, lang::dim::temperature, true)
                    : lang::format_value(v, in.key->dim),
        fmt::format("{:g}", t)));
  }
}

} // namespace thermnet
