#include "lang/time_program.hpp"

#include "lang/units.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string_view>

namespace thermnet::lang {
namespace {

using Code = TimeProgram::Op::Code;

/// The instruction of a one-argument function, by name.
Code function_code(std::string_view f) {
  static const std::pair<std::string_view, Code> table[] = {
      {"exp", Code::exp}, {"log", Code::log}, {"log10", Code::log10}, {"sin", Code::sin},
      {"cos", Code::cos}, {"tan", Code::tan}, {"sqrt", Code::sqrt},   {"abs", Code::abs},
      {"min", Code::min}, {"max", Code::max}, {"pow", Code::power}};
  for (const auto& [name, code] : table)
    if (name == f) return code;
  throw std::logic_error("compile_time_program: unknown function (not checked before)");
}

/// Visits the nodes of an expression in postfix order without recursion.
template <typename Visit> void postfix(const ast::File& file, ast::Index root, Visit&& visit) {
  using NodeOp = ast::ExprNode::Op;
  struct Frame {
    ast::Index node;
    std::uint32_t next = 0; // children visited so far
  };
  std::vector<Frame> stack{{root}};
  while (!stack.empty()) {
    Frame& fr = stack.back();
    const ast::ExprNode& n = file.node(fr.node);
    std::uint32_t children = 0;
    ast::Index child = ast::none;
    switch (n.op) {
    case NodeOp::negate:
    case NodeOp::group:
      children = 1;
      child = n.a;
      break;
    case NodeOp::add:
    case NodeOp::subtract:
    case NodeOp::multiply:
    case NodeOp::divide:
    case NodeOp::power:
      children = 2;
      child = fr.next == 0 ? n.a : n.b;
      break;
    case NodeOp::call:
      children = static_cast<std::uint32_t>(file.call_args(n).size());
      if (fr.next < children) child = file.call_args(n)[fr.next];
      break;
    default:
      break;
    }
    if (fr.next < children) {
      ++fr.next;
      stack.push_back({child});
      continue;
    }
    visit(n, fr.node);
    stack.pop_back();
  }
}

} // namespace

double TimeProgram::at(double t) const {
  std::array<double, 64> small; // NOLINT: written before read (a stack machine)
  std::vector<double> large;
  double* stack = small.data();
  if (max_depth > small.size()) {
    large.resize(max_depth);
    stack = large.data();
  }
  std::size_t top = 0;
  for (const Op& op : ops) {
    switch (op.code) {
    case Code::constant:
      stack[top++] = op.value;
      break;
    case Code::time:
      stack[top++] = t;
      break;
    case Code::negate:
      stack[top - 1] = -stack[top - 1];
      break;
    case Code::add:
      --top;
      stack[top - 1] += stack[top];
      break;
    case Code::subtract:
      --top;
      stack[top - 1] -= stack[top];
      break;
    case Code::multiply:
      --top;
      stack[top - 1] *= stack[top];
      break;
    case Code::divide:
      --top;
      stack[top - 1] /= stack[top];
      break;
    case Code::power:
      --top;
      stack[top - 1] = std::pow(stack[top - 1], stack[top]);
      break;
    case Code::exp:
      stack[top - 1] = std::exp(stack[top - 1]);
      break;
    case Code::log:
      stack[top - 1] = std::log(stack[top - 1]);
      break;
    case Code::log10:
      stack[top - 1] = std::log10(stack[top - 1]);
      break;
    case Code::sin:
      stack[top - 1] = std::sin(stack[top - 1]);
      break;
    case Code::cos:
      stack[top - 1] = std::cos(stack[top - 1]);
      break;
    case Code::tan:
      stack[top - 1] = std::tan(stack[top - 1]);
      break;
    case Code::sqrt:
      stack[top - 1] = std::sqrt(stack[top - 1]);
      break;
    case Code::abs:
      stack[top - 1] = std::abs(stack[top - 1]);
      break;
    case Code::min:
    case Code::max: {
      const std::size_t first = top - op.count;
      double acc = stack[first];
      for (std::size_t i = first + 1; i < top; ++i)
        acc = op.code == Code::min ? std::min(acc, stack[i]) : std::max(acc, stack[i]);
      top = first;
      stack[top++] = acc;
      break;
    }
    case Code::signal:
      stack[top++] = signals[op.count].at(t);
      break;
    }
  }
  return top ? stack[top - 1] : 0.0;
}

std::vector<double> TimeProgram::corners() const {
  std::vector<double> out;
  for (const Signal& s : signals)
    out.insert(out.end(), s.corners().begin(), s.corners().end());
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

bool TimeProgram::piecewise_linear() const {
  // The degree of each stack entry in the time: 0 constant, 1 linear between corners; anything
  // else (a product of two varying terms, a function of a varying term) is not piecewise linear.
  std::vector<int> degree;
  degree.reserve(max_depth);
  for (const Op& op : ops) {
    switch (op.code) {
    case Code::constant:
      degree.push_back(0);
      break;
    case Code::time:
      degree.push_back(1);
      break;
    case Code::signal: {
      const Signal& s = signals[op.count];
      if (!s.piecewise_linear()) return false;
      degree.push_back(s.is_constant() ? 0 : 1);
      break;
    }
    case Code::negate:
      break;
    case Code::add:
    case Code::subtract: {
      const int b = degree.back();
      degree.pop_back();
      degree.back() = std::max(degree.back(), b);
      break;
    }
    case Code::multiply: {
      const int b = degree.back();
      degree.pop_back();
      degree.back() += b;
      if (degree.back() > 1) return false;
      break;
    }
    case Code::divide: {
      const int b = degree.back();
      degree.pop_back();
      if (b != 0) return false;
      break;
    }
    case Code::min:
    case Code::max: {
      const std::size_t first = degree.size() - op.count;
      if (std::any_of(degree.begin() + static_cast<std::ptrdiff_t>(first), degree.end(),
                      [](int d) { return d != 0; }))
        return false;
      degree.resize(first + 1);
      break;
    }
    case Code::power: {
      const int b = degree.back();
      degree.pop_back();
      if (b != 0 || degree.back() != 0) return false;
      break;
    }
    default: // exp, log, log10, sin, cos, tan, sqrt, abs: of a constant only
      if (degree.back() != 0) return false;
      break;
    }
  }
  return true;
}

std::string TimeProgram::text() const {
  std::vector<std::string> stack;
  auto unary = [&](const char* f) { stack.back() = fmt::format("{}({})", f, stack.back()); };
  auto binary = [&](const char* op) {
    std::string b = std::move(stack.back());
    stack.pop_back();
    stack.back() = fmt::format("({} {} {})", stack.back(), op, b);
  };
  for (const Op& op : ops) {
    switch (op.code) {
    case Code::constant:
      stack.push_back(fmt::format("{:.17g}", op.value));
      break;
    case Code::time:
      stack.emplace_back("time");
      break;
    case Code::negate:
      stack.back() = "(-" + stack.back() + ")";
      break;
    case Code::add:
      binary("+");
      break;
    case Code::subtract:
      binary("-");
      break;
    case Code::multiply:
      binary("*");
      break;
    case Code::divide:
      binary("/");
      break;
    case Code::power:
      binary("^");
      break;
    case Code::exp:
      unary("exp");
      break;
    case Code::log:
      unary("log");
      break;
    case Code::log10:
      unary("log10");
      break;
    case Code::sin:
      unary("sin");
      break;
    case Code::cos:
      unary("cos");
      break;
    case Code::tan:
      unary("tan");
      break;
    case Code::sqrt:
      unary("sqrt");
      break;
    case Code::abs:
      unary("abs");
      break;
    case Code::min:
    case Code::max: {
      std::string args;
      for (std::size_t i = stack.size() - op.count; i < stack.size(); ++i)
        args += (args.empty() ? "" : ", ") + stack[i];
      stack.resize(stack.size() - op.count);
      stack.push_back(fmt::format("{}({})", op.code == Code::min ? "min" : "max", args));
      break;
    }
    case Code::signal:
      stack.push_back(signals[op.count].text());
      break;
    }
  }
  return stack.empty() ? std::string() : stack.back();
}

std::shared_ptr<const TimeProgram>
compile_time_program(const ast::File& file, ast::Index root,
                     const std::function<double(const ast::Identifier&)>& value_of,
                     const std::function<Signal(ast::Index node)>& signal_of) {
  using NodeOp = ast::ExprNode::Op;
  auto program = std::make_shared<TimeProgram>();
  std::size_t depth = 0;
  auto emit = [&](Code code, int pops, int pushes, double value = 0, std::uint32_t count = 0) {
    program->ops.push_back({code, count, value});
    depth = depth - static_cast<std::size_t>(pops) + static_cast<std::size_t>(pushes);
    program->max_depth = std::max(program->max_depth, depth);
  };
  postfix(file, root, [&](const ast::ExprNode& n, ast::Index index) {
    switch (n.op) {
    case NodeOp::signal:
    case NodeOp::ref:
      if (!signal_of) throw std::logic_error("compile_time_program: a signal without signal_of");
      program->signals.push_back(signal_of(index));
      emit(Code::signal, 0, 1, 0, static_cast<std::uint32_t>(program->signals.size() - 1));
      break;
    case NodeOp::number:
      emit(Code::constant, 0, 1, n.value);
      break;
    case NodeOp::quantity: {
      const Unit u = parse_unit(file.units[n.a].text);
      emit(Code::constant, 0, 1, u.scale * n.value + u.offset);
      break;
    }
    case NodeOp::name: {
      const ast::Identifier& id = file.names[n.a];
      if (id.name == "pi")
        emit(Code::constant, 0, 1, 3.14159265358979323846);
      else if (id.name == "sigma")
        emit(Code::constant, 0, 1, 5.670374419e-8);
      else if (id.name == "time")
        emit(Code::time, 0, 1);
      else
        emit(Code::constant, 0, 1, value_of(id));
      break;
    }
    case NodeOp::negate:
      emit(Code::negate, 1, 1);
      break;
    case NodeOp::group:
      break;
    case NodeOp::add:
      emit(Code::add, 2, 1);
      break;
    case NodeOp::subtract:
      emit(Code::subtract, 2, 1);
      break;
    case NodeOp::multiply:
      emit(Code::multiply, 2, 1);
      break;
    case NodeOp::divide:
      emit(Code::divide, 2, 1);
      break;
    case NodeOp::power:
      emit(Code::power, 2, 1);
      break;
    case NodeOp::call: {
      const Code code = function_code(file.names[n.a].name);
      const auto count = static_cast<std::uint32_t>(file.call_args(n).size());
      emit(code, static_cast<int>(count), 1, 0, count);
      break;
    }
    }
  });
  return program;
}

} // namespace thermnet::lang
