#include "lang/network_spec.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace thermnet::lang {

KeySignals::iterator KeySignals::lower_bound(std::string_view key) {
  return std::lower_bound(
      items_.begin(), items_.end(), key,
      [](const value_type& item, std::string_view k) { return item.first < k; });
}

KeySignals::iterator KeySignals::find(std::string_view key) {
  auto it = lower_bound(key);
  return it != items_.end() && it->first == key ? it : items_.end();
}

KeySignals::const_iterator KeySignals::find(std::string_view key) const {
  return const_cast<KeySignals*>(this)->find(key);
}

Signal& KeySignals::at(std::string_view key) {
  auto it = find(key);
  if (it == items_.end()) throw std::out_of_range(fmt::format("no key '{}'", key));
  return it->second;
}

const Signal& KeySignals::at(std::string_view key) const {
  return const_cast<KeySignals*>(this)->at(key);
}

Signal& KeySignals::operator[](const KeySchema& key) {
  return emplace(key, Signal{}).first->second;
}

std::pair<KeySignals::iterator, bool> KeySignals::emplace(const KeySchema& key, Signal value) {
  const std::string_view name = key.name;
  auto it = lower_bound(name);
  if (it != items_.end() && it->first == name) return {it, false};
  return {items_.emplace(it, name, std::move(value)), true};
}

const std::string& NodeSpec::doc() const {
  static const std::string none;
  return doc_.get() ? *doc_.get() : none;
}

void NodeSpec::set_doc(std::string_view text) {
  if (!text.empty() || doc_.get()) doc_.make() = text;
}

std::string_view ElementSpec::kind() const {
  if (schema) return schema->kind;
  switch (composite_) {
  case Composite::series:
    return "series";
  case Composite::parallel:
    return "parallel";
  case Composite::none:
    break;
  }
  return {};
}

void ElementSpec::set_nodes(std::span<const int> nodes) {
  const bool many = schema && schema->observes; // a sensor of the mean of several nodes
  if (nodes.empty() || (nodes.size() > nodes_.size() && !many) || nodes.size() > 255)
    throw std::invalid_argument(
        fmt::format("element '{}' has {} terminals (1 or 2 allowed)", name, nodes.size()));
  terminals_ = static_cast<std::uint8_t>(nodes.size());
  if (nodes.size() <= nodes_.size()) {
    std::copy(nodes.begin(), nodes.end(), nodes_.begin());
    if (Extras* x = extras_.get()) x->nodes.clear();
    return;
  }
  extras_.make().nodes.assign(nodes.begin(), nodes.end());
}

std::span<const int> ElementSpec::nodes() const {
  if (terminals_ > nodes_.size()) return extras_.get()->nodes;
  return {nodes_.data(), terminals_};
}

std::span<const ElementSpec> ElementSpec::parts() const {
  if (const Extras* x = extras_.get()) return x->parts;
  return {};
}

std::vector<ElementSpec>& ElementSpec::edit_parts() {
  return extras_.make().parts;
}

void ElementSpec::set(std::string_view key, Signal value) {
  const KeySchema* ks = schema ? schema->key(key) : nullptr;
  if (!ks)
    throw std::invalid_argument(fmt::format("element kind '{}' has no key '{}'", kind(), key));
  values[*ks] = std::move(value);
}

std::optional<int> ElementSpec::node_key(std::string_view key) const {
  if (const Extras* x = extras_.get())
    for (const auto& [name, node] : x->node_keys)
      if (name == key) return node;
  return std::nullopt;
}

void ElementSpec::add_node_key(const KeySchema& key, int node) {
  extras_.make().node_keys.emplace_back(key.name, node);
}

KeyValues ElementSpec::key_values() const {
  KeyValues kv;
  for (const auto& [k, s] : values)
    if (s.is_constant()) kv.emplace(k, s.constant);
  return kv;
}

int NetworkSpec::node_index(const std::string& name) const {
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].name == name) return static_cast<int>(i);
  return -1;
}

} // namespace thermnet::lang
