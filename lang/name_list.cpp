#include "lang/name_list.hpp"

namespace thermnet::lang {

std::vector<std::string> join_bracketed(const std::vector<std::string>& pieces) {
  std::vector<std::string> out;
  int open = 0; // brackets left open by the name being joined
  for (const auto& p : pieces) {
    if (open > 0)
      out.back() += "," + p;
    else
      out.push_back(p);
    for (char c : p)
      open += c == '[' ? 1 : c == ']' ? -1 : 0;
    if (open < 0) open = 0;
  }
  return out;
}

} // namespace thermnet::lang
