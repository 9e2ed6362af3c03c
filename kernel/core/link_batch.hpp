#pragma once
/// Constant-conductance links of a network in flat arrays: stamped in one loop without virtual
/// calls or pointer chasing (large networks are mostly such links).

#include "kernel/core/element.hpp"

#include <utility>
#include <vector>

namespace thermnet {

/// Linear two-terminal links Q = G (T_a - T_b), stored as structure of arrays.
class LinkBatch {
public:
  /// Appends a link between spec nodes a and b with conductance G (W/K).
  void add(int a, int b, double G);
  /// Number of links.
  std::size_t size() const { return G_.size(); }
  /// Requests the Jacobian slots of every link (as Element::declare).
  void declare(JacobianLayout& layout);
  /// Heat flow of link k from its first node to its second at temperatures T (all nodes), W.
  double flow(std::size_t k, const double* T) const {
    return G_[k] * (T[ends_[k].a] - T[ends_[k].b]);
  }
  /// Conductance of link k, W/K.
  double conductance(std::size_t k) const { return G_[k]; }
  /// First and second node of link k.
  std::pair<int, int> nodes(std::size_t k) const { return {ends_[k].a, ends_[k].b}; }
  /// Adds every link's heat flow into F (all nodes, W).
  void stamp_flows(const double* T, double* F) const;
  /// Adds every link's derivatives into J (the slots handed out by declare, W/K).
  void stamp_jacobian(double* J) const;

private:
  struct Ends {
    int a, b;
  };
  std::vector<Ends> ends_;
  std::vector<double> G_;
  std::vector<int> slots_; // aa, ab, ba, bb per link
};

} // namespace thermnet
