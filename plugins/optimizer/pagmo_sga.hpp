#pragma once
/// The uses of pagmo2 (the 'ga' optimizer's sga, `design`'s compass search), kept in a library of
/// their own (libthermnet_pagmo_sga) that is loaded the first time one runs: loading pagmo costs
/// every process 25-30 ms and 35 MB of resident memory in its static initialisers (measured with
/// an empty program linked with and without it), which `simulate`, `lint` and the others never
/// need.

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

/// What pagmo's compass search is asked to minimise: a function of the unit box, from a start.
struct CompassRequest {
  std::vector<double> start;    ///< start point, in [0, 1]^p
  unsigned max_evaluations = 0; ///< evaluations of fitness at most
  double start_range = 0.1;     ///< first step, a share of the box
  double stop_range = 1e-3;     ///< the search stops when the step falls below this share
  double reduction = 0.5;       ///< the step's factor after a failed poll
  std::function<double(const std::vector<double>&)> fitness; ///< what to minimise (serial)
};

/// The compass-search entry point of libthermnet_pagmo_sga.
using CompassSearch = void (*)(const CompassRequest&);

/// Loads libthermnet_pagmo_sga (once per process) and returns its compass search; throws
/// std::runtime_error as load_pagmo_sga() does.
CompassSearch load_pagmo_compass();

} // namespace thermnet
