// Judging refitted candidates: significance, one finding per site whatever its mechanisms (named
// only when the data tell them apart), and the ranking.

#include "kernel/diagnosis/selection.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

namespace thermnet::detail {

void note_mechanism(Finding& keep, const Finding& drop, const FitComparison& cmp,
                    const std::vector<std::string>& mechanisms) {
  keep.mechanism_z = cmp.z;
  keep.mechanism_identified = cmp.separable;
  const std::string numbers = fmt::format(
      "RMSE {:.4g} vs {:.4g} K, held-out {:.4g} vs {:.4g} K; difference {:.2g} times its "
      "spread over {:.0f} independent points",
      keep.rmse_after, drop.rmse_after, keep.validation_rmse_after, drop.validation_rmse_after,
      cmp.z, cmp.n_eff);
  keep.mechanism_note =
      cmp.separable ? fmt::format("{} fits better than {} ({})", keep.candidate.mechanism,
                                  drop.candidate.mechanism, numbers)
                    : fmt::format("{} fit equally ({}); kept {}", fmt::join(mechanisms, " and "),
                                  numbers, keep.candidate.mechanism);
}

void Selection::judge(std::vector<Evaluated>& res) const {
  // Better by the information criterion, not worse on held-out data, a real drop of the error.
  const double nf = engine_.evidence().noise_floor;
  for (auto& e : res) {
    Finding& f = e.f;
    f.significant = !f.values.empty() && f.delta_bic < -10.0 &&
                    f.validation_rmse_after <= f.validation_rmse_before + 0.1 * nf &&
                    f.rmse_after < 0.97 * f.rmse_before;
  }
}

void Selection::merge_mechanisms(const std::vector<Entry>& entries,
                                 std::vector<Evaluated>& res) const {
  // One site refitted with two mechanisms (a link as linear and as radiation): one finding. The
  // mechanism is named only when the data tell them apart (compare_fits: the SSE difference beyond
  // the spread of an SSE over the independent points, and the better one also better on held-out
  // data).
  for (std::size_t i = 0; i < res.size(); ++i)
    for (std::size_t j = i + 1; j < res.size(); ++j) {
      Evaluated &a = res[i], &b = res[j];
      if (a.f.values.empty() || b.f.values.empty() || a.f.candidate.mechanism.empty() ||
          site(a.f.candidate) != site(b.f.candidate) ||
          a.f.candidate.mechanism == b.f.candidate.mechanism)
        continue;
      const FitComparison cmp =
          compare_fits({a.r, a.holdout_sse}, {b.r, b.holdout_sse}, engine_.evidence().noise_floor);
      Evaluated& keep = cmp.first_better ? a : b;
      Evaluated& drop = cmp.first_better ? b : a;
      note_mechanism(keep.f, drop.f, cmp, entries[i].own_h->mechanisms());
      drop.f.values.clear(); // merged into keep
    }
}

double Selection::score(const Finding& f) const {
  // Predictive error on held-out data plus the information criterion on all data.
  const double na = static_cast<double>(engine_.points());
  const double nt = std::max(1.0, static_cast<double>(engine_.held_out_points()));
  const double all2 = std::max(f.rmse_after * f.rmse_after, 1e-300);
  const double hold2 = std::max(f.validation_rmse_after * f.validation_rmse_after, 1e-300);
  return nt * std::log(hold2) + na * std::log(all2) +
         static_cast<double>(f.values.size()) * std::log(na);
}

std::vector<std::size_t> Selection::ranked(const std::vector<Evaluated>& res) const {
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < res.size(); ++i)
    if (!res[i].f.values.empty() && res[i].f.significant) idx.push_back(i);
  std::stable_sort(idx.begin(), idx.end(),
                   [&](std::size_t a, std::size_t b) { return score(res[a].f) < score(res[b].f); });
  return idx;
}

} // namespace thermnet::detail
