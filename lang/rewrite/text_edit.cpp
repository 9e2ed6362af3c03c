#include "lang/rewrite/text_edit.hpp"

#include <algorithm>

namespace thermnet::rewrite {

std::string apply_edits(std::string text, std::vector<TextEdit> edits) {
  // From the end of the text backwards, so earlier offsets stay valid.
  std::sort(edits.begin(), edits.end(),
            [](const TextEdit& a, const TextEdit& b) { return a.begin > b.begin; });
  for (const auto& e : edits)
    text.replace(e.begin, e.end - e.begin, e.text);
  return text;
}

bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

} // namespace thermnet::rewrite
