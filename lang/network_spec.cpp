#include "lang/network_spec.hpp"

namespace thermnet::lang {

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
