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

Signal& KeySignals::operator[](std::string_view key) {
  return emplace(key, Signal{}).first->second;
}

std::pair<KeySignals::iterator, bool> KeySignals::emplace(std::string_view key, Signal value) {
  auto it = lower_bound(key);
  if (it != items_.end() && it->first == key) return {it, false};
  return {items_.emplace(it, std::string(key), std::move(value)), true};
}

std::optional<int> ElementSpec::node_key(std::string_view key) const {
  for (const auto& [name, node] : node_keys)
    if (name == key) return node;
  return std::nullopt;
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
