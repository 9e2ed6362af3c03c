#pragma once
/// Foster and Cauer forms of a thermal impedance. A Foster network is R || C cells in series
/// (datasheets give junction-to-case impedance so): its inner nodes are not temperatures of
/// anything. The Cauer ladder with the same impedance Z(s) seen from its driven end (the far end
/// held) has a capacity at each node, to a fixed temperature, and resistances between them: a
/// network thermnet can write. The conversion is a Lanczos tridiagonalisation of the Foster
/// network's diagonal state matrix (full reorthogonalisation, long double), checked afterwards.

#include <stdexcept>
#include <vector>

namespace thermnet::importer {

/// One cell of a Foster network: a resistance [K/W] in parallel with a capacitance [J/K].
struct FosterCell {
  double R = 0; ///< resistance [K/W]
  double C = 0; ///< capacitance [J/K]
};

/// One stage of a Cauer ladder: the capacity at node k (node 1: the driven end) and the
/// resistance from node k to node k+1 (the last one: to the held far end).
struct CauerStage {
  double C = 0; ///< capacity at the node [J/K]
  double R = 0; ///< resistance to the next node [K/W]
};

/// A Foster network that cannot be converted (bad values, or a conversion that fails its check).
struct FosterError : std::domain_error {
  using std::domain_error::domain_error;
};

/// The Cauer ladder with the same Z(s) as the Foster cells (cells with equal time constants are
/// merged first); throws FosterError for non-positive or non-finite values, or when Z(s) of the
/// ladder differs from the Foster network's by more than 1e-9 (relative) at s = 0 and around
/// every cell's 1/tau.
std::vector<CauerStage> foster_to_cauer(const std::vector<FosterCell>& cells);

/// Z(s) of a Foster network at a real s >= 0: the sum of R / (1 + s R C).
double foster_impedance(const std::vector<FosterCell>& cells, double s);

/// Z(s) of a Cauer ladder at a real s >= 0, its far end held.
double cauer_impedance(const std::vector<CauerStage>& stages, double s);

/// Zth(t), the temperature rise of the driven end per watt of a heat step at t = 0: the sum of
/// R (1 - exp(-t / (R C))).
double foster_step_response(const std::vector<FosterCell>& cells, double t);

} // namespace thermnet::importer
