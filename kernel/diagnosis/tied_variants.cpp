// The first finding against its neighbours. A link from a node to a boundary and a link to a node
// an element ties to that boundary run at nearly the same temperature and fit alike; so do a link
// between two nodes and a link from one of them to a neighbour of the other (a box joined to the
// panel cell under another box, or to that box). The screen ranks sites by the measured nodes'
// heat flows and may refit only one of them. The best candidate's counterparts on the tied nodes,
// and a link's on its ends' neighbours, are refitted too (jointly with the ranged params when
// those were recalibrated), so that they compete with it or stand beside it as rivals the data
// cannot tell apart.

#include "kernel/diagnosis/selection.hpp"

#include <algorithm>

namespace thermnet::detail {

bool Selection::refit_tied_variants(std::size_t recal, DiagnosisReport& rep) {
  if (first_.empty() || !model_side(chosen_[first_.front()])) return false;
  const Candidate& best = chosen_[first_.front()].own;
  const bool joint = recal < chosen_.size();
  std::vector<Entry> entries;
  std::vector<std::size_t> variants = tied_node_exchanges(side_, engine_.evidence(), best);
  for (std::size_t j : neighbour_exchanges(side_, engine_.evidence(), best))
    if (std::find(variants.begin(), variants.end(), j) == variants.end()) variants.push_back(j);
  for (std::size_t j : variants)
    if (std::none_of(chosen_.begin(), chosen_.end(),
                     [&](const Entry& x) { return same_candidate(x.own, side_[j].c); }))
      entries.push_back(joint ? joint_entry(side_[j], recal, res_[recal].f.values) : side_[j]);
  if (entries.empty()) return false;
  std::vector<Evaluated> r = engine_.evaluate_all(entries, engine_.declared(), joint);
  rep.refitted += entries.size();
  for (std::size_t k = 0; k < entries.size(); ++k) {
    if (joint && !r[k].f.values.empty()) note_joint(r[k].f, recal);
    chosen_.push_back(std::move(entries[k]));
    res_.push_back(std::move(r[k]));
  }
  return true;
}

} // namespace thermnet::detail
