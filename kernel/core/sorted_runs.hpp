#pragma once
/// Merging runs of times into one increasing list without duplicates (breakpoints, step grids).

#include <algorithm>
#include <iterator>
#include <vector>

namespace thermnet {

/// Merges the times [first, last) (increasing or not) into `into` (increasing, no duplicates),
/// which stays so; a run already contained in it adds nothing and costs no merge.
template <class It> void merge_sorted_run(std::vector<double>& into, It first, It last) {
  if (first == last) return;
  if (std::is_sorted(first, last) && std::includes(into.begin(), into.end(), first, last)) return;
  const auto mid = static_cast<std::ptrdiff_t>(into.size());
  into.insert(into.end(), first, last);
  if (!std::is_sorted(into.begin() + mid, into.end())) std::sort(into.begin() + mid, into.end());
  std::inplace_merge(into.begin(), into.begin() + mid, into.end());
  into.erase(std::unique(into.begin(), into.end()), into.end());
}

} // namespace thermnet
