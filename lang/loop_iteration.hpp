#pragma once
/// The iterations of a `for` header without recursion: a header may name any number of variables
/// (`for a in 1 .. 2, b in a .. 3, ...`), and a later range may use the variables before it.

#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

namespace thermnet::lang {

/// The first and last value of one loop variable (last < first: no value).
using LoopBounds = std::pair<long, long>;

/// Runs `body()` once per combination of the values of a header's `count` variables, the first
/// outermost, with `values` holding the current value of each. `bounds(k)` gives the range of
/// variable k while `values` holds those before it (nullopt stops the whole loop); `step()` is
/// called for every value a variable takes, before it is taken. A false from `step` or `body`
/// stops. Returns false when stopped.
template <class Bounds, class Step, class Body>
bool for_each_iteration(std::size_t count, std::vector<long>& values, Bounds bounds, Step step,
                        Body body) {
  std::vector<long> last(count);
  values.clear();
  for (;;) {
    bool empty = false; // a variable without values: no iteration below the ones before it
    while (values.size() < count) {
      const std::size_t k = values.size();
      const std::optional<LoopBounds> r = bounds(k);
      if (!r) return false;
      if (r->second < r->first) {
        empty = true;
        break;
      }
      if (!step()) return false;
      last[k] = r->second;
      values.push_back(r->first);
    }
    if (!empty && !body()) return false;
    // The innermost variable with a value left takes it; those inside it start again.
    while (!values.empty() && values.back() == last[values.size() - 1])
      values.pop_back();
    if (values.empty()) return true;
    if (!step()) return false;
    ++values.back();
  }
}

} // namespace thermnet::lang
