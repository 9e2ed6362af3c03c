#include "app/schema_text.hpp"

#include <fmt/format.h>

namespace thermnet::app {

std::string key_default(const lang::KeySchema& k) {
  if (k.default_value) return fmt::format("{:g}", *k.default_value);
  if (k.required) return "required";
  return "optional";
}

std::string key_table_markdown(const lang::ElementSchema& s) {
  std::string out = "| key | unit | default | valid | description |\n|---|---|---|---|---|\n";
  for (const auto& k : s.keys)
    out += fmt::format("| `{}` | {} | {} | {} | {} |\n", k.name, key_unit(k), key_default(k),
                       k.range_text(), k.doc);
  return out;
}

std::string alternatives_text(const lang::ElementSchema& s) {
  std::string groups;
  for (const auto& g : s.alternatives) {
    std::string names;
    for (const auto& n : g)
      names += (names.empty() ? "" : " + ") + n;
    groups += (groups.empty() ? "" : ", or ") + names;
  }
  return groups;
}

std::string key_unit(const lang::KeySchema& k) {
  if (k.type == lang::KeyType::node) return "node";
  if (k.absolute_temperature) return "degC";
  return lang::describe(k.dim);
}

std::string kind_markdown(const lang::ElementSchema& s) {
  std::string out = fmt::format("**{}** — element kind, {} terminal{}\n\n{}\n\n", s.kind,
                                s.terminals, s.terminals == 1 ? "" : "s", s.doc);
  out += key_table_markdown(s);
  if (!s.alternatives.empty())
    out += fmt::format("\nGive exactly one of: {}.\n", alternatives_text(s));
  return out;
}

std::string key_markdown(const lang::ElementSchema& s, const lang::KeySchema& k) {
  std::string out = fmt::format("**{}** — key of `{}`\n\n{}\n\nunit: `{}`; {}", k.name, s.kind,
                                k.doc, key_unit(k), key_default(k));
  if (!k.range_text().empty()) out += fmt::format("; valid {}", k.range_text());
  if (k.type == lang::KeyType::signal) out += "; accepts a signal (step, pwl, table)";
  return out;
}

const std::vector<std::pair<std::string, std::string>>& builtin_keys(std::string_view statement) {
  static const std::vector<std::pair<std::string, std::string>> node = {
      {"C", "heat capacity [J/K]"}, {"T0", "initial temperature [degC]"}};
  static const std::vector<std::pair<std::string, std::string>> boundary = {
      {"T", "prescribed temperature [degC], a constant or a signal"}};
  static const std::vector<std::pair<std::string, std::string>> case_keys = {
      {"duration", "simulated time [s]"},
      {"initial", "initial state: `steady` starts from the steady state"},
      {"output", "output sampling interval [s]"},
      {"data", "measured data file (CSV) of the case"}};
  static const std::vector<std::pair<std::string, std::string>> none;
  if (statement == "node") return node;
  if (statement == "boundary") return boundary;
  if (statement == "case") return case_keys;
  return none;
}

std::string element_kind(const lang::Model& m, std::string_view name) {
  const int i = m.element_index(name);
  if (i < 0) return {};
  const lang::ElementDecl& e = m.elements()[static_cast<std::size_t>(i)];
  if (e.element) return std::string(e.element->kind.name);
  if (e.composite) return std::string(e.composite->mode.name);
  return {};
}

const lang::NodeDecl* find_node(const lang::Model& m, std::string_view name) {
  const int i = m.node_index(name);
  return i < 0 ? nullptr : &m.nodes()[static_cast<std::size_t>(i)];
}

} // namespace thermnet::app
