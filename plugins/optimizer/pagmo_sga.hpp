#pragma once
/// The 'ga' optimizer's use of pagmo2, kept in a library of its own (libthermnet_pagmo_sga) that
/// is loaded the first time 'ga' runs: loading pagmo costs every process about 0.1 s and 4,000
/// page faults in its static initialisers, which `simulate`, `lint` and the others never need.

#include <cstddef>
#include <functional>
#include <vector>

namespace thermnet {

/// What pagmo's sga is asked to evolve: a population in the unit box, already evaluated.
struct SgaRequest {
  std::vector<std::vector<double>> initial; ///< initial population, points of [0, 1]^p
  std::vector<double> initial_fitness;      ///< their fitness (SSE), same order
  std::size_t generations = 0;              ///< generations to evolve
  unsigned seed = 1;                        ///< seed of the population and of sga
  std::function<double(const std::vector<double>&)> fitness; ///< fitness of a point (serial)
  std::function<bool()> cancelled; ///< true stops before the next generation
};

/// What came out of the evolution.
struct SgaOutcome {
  std::size_t generations = 0;    ///< generations evolved (fewer if cancelled)
  std::vector<double> champion_x; ///< best point found, in the unit box
  double champion_fitness = 0.0;  ///< its fitness
};

/// The entry point of libthermnet_pagmo_sga.
using SgaEvolve = SgaOutcome (*)(const SgaRequest&);

/// Loads libthermnet_pagmo_sga (once per process) and returns its entry point; throws
/// std::runtime_error saying where it looked if the library cannot be loaded.
SgaEvolve load_pagmo_sga();

} // namespace thermnet
