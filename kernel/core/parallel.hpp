#pragma once
/// Work spread over threads with results that do not depend on the thread count: an index loop on a
/// small pool, and counter-based random numbers (a value per (seed, stream, index), any order).

#include <atomic>
#include <cstdint>
#include <functional>

namespace thermnet {

/// Runs body(i) for i in [0, n) on `threads` workers (0: all cores); results must be written by
/// index so the outcome does not depend on the number of threads. Stops early when cancel is set.
void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t)>& body,
                  const std::atomic<bool>* cancel = nullptr);

/// A reproducible uniform random number in [0, 1) for (seed, stream, index): independent of
/// evaluation order and thread count.
double uniform01(std::uint64_t seed, std::uint64_t stream, std::uint64_t index);

/// A seed for the draws of one variant of a run (e.g. a sample count), derived from the user's seed
/// and the variant's key: different keys give independent streams for the same seed.
std::uint64_t derived_seed(std::uint64_t seed, std::uint64_t key);

} // namespace thermnet
