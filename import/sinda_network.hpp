#pragma once
/// A SINDA/FLUINT deck as a thermnet network: node N of submodel SUB is SUB[N], conductor N (and
/// radiation conductor -N) is SUB_G[N], the heat load on node N is SUB_Q[N]; units as the control
/// data say (sinda_units.hpp); every node a conductor or load names is checked.

#include "import/network.hpp"
#include "import/report.hpp"
#include "import/sinda_deck.hpp"

namespace thermnet::importer::sinda {

/// Builds the network of a deck; errors and notes go to `report` (the network is incomplete when
/// it holds errors).
Network deck_network(const Deck& deck, Report& report);

} // namespace thermnet::importer::sinda
