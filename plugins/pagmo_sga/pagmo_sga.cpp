// libthermnet_pagmo_sga: pagmo2's simple genetic algorithm (pagmo::sga) over the unit box, for the
// 'ga' optimizer (plugins/optimizer/ga.cpp), and its compass search, for `design`
// (app/design_search.cpp). Only this library links pagmo, so processes that run neither do not
// pay for pagmo's static initialisers (plugins/optimizer/pagmo_sga.hpp).
//
// Operators. Simulated binary crossover (probability 0.9, distribution index 10), polynomial
// mutation (probability 1/p per gene, distribution index 20), tournament selection of size 2
// and sga's pure elitism (the best of parents and children survive): the champion never gets
// worse. sga evaluates its offspring one by one through the problem's fitness(), serially.

#include "plugins/optimizer/pagmo_sga.hpp"

#include <pagmo/algorithms/compass_search.hpp>
#include <pagmo/algorithms/sga.hpp>
#include <pagmo/population.hpp>
#include <pagmo/problem.hpp>

#include <string>
#include <utility>

namespace {

/// The compass search's problem: the unit box of the start's dimension, fitness from the request.
struct CompassProblem {
  const thermnet::CompassRequest* request = nullptr;
  pagmo::vector_double fitness(const pagmo::vector_double& u) const {
    return {request->fitness(u)};
  }
  std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const {
    const std::size_t p = request->start.size();
    return {pagmo::vector_double(p, 0.0), pagmo::vector_double(p, 1.0)};
  }
  std::string get_name() const { return "thermnet design"; }
};

/// The pagmo user-defined problem: the unit box, fitness from the request.
struct UnitBoxProblem {
  const thermnet::SgaRequest* request = nullptr;
  pagmo::vector_double fitness(const pagmo::vector_double& u) const {
    return {request->fitness(u)};
  }
  std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const {
    const std::size_t p = request->initial.front().size();
    return {pagmo::vector_double(p, 0.0), pagmo::vector_double(p, 1.0)};
  }
  std::string get_name() const { return "thermnet calibration"; }
};

} // namespace

/// Evolves the request's population with pagmo::sga (the library's entry point).
extern "C" __attribute__((visibility("default"))) thermnet::SgaOutcome
thermnet_pagmo_sga_evolve(const thermnet::SgaRequest& request) {
  const std::size_t p = request.initial.front().size();
  pagmo::problem prob{UnitBoxProblem{&request}};
  pagmo::population pop{prob, 0u, request.seed};
  for (std::size_t i = 0; i < request.initial.size(); ++i)
    pop.push_back(request.initial[i], {request.initial_fitness[i]});
  pagmo::sga algo{1u,           0.9,         10.0,  1.0 / static_cast<double>(p),
                  20.0,         2u,          "sbx", "polynomial",
                  "tournament", request.seed};
  thermnet::SgaOutcome outcome;
  for (; outcome.generations < request.generations; ++outcome.generations) {
    if (request.cancelled && request.cancelled()) break;
    pop = algo.evolve(pop);
  }
  outcome.champion_x = pop.champion_x();
  outcome.champion_fitness = pop.champion_f()[0];
  return outcome;
}

/// Minimises the request's fitness with pagmo::compass_search from its start (the library's
/// second entry point).
extern "C" __attribute__((visibility("default"))) void
thermnet_pagmo_compass_search(const thermnet::CompassRequest& request) {
  pagmo::problem prob{CompassProblem{&request}};
  pagmo::population pop{prob};
  pop.push_back(request.start);
  pagmo::compass_search algo(request.max_evaluations, request.start_range, request.stop_range,
                             request.reduction);
  algo.evolve(pop);
}
