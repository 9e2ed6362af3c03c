// A diagnosis refit travels between processes (MPI ranks) as bytes: what arrives is what was
// computed, bit for bit, for a failed refit too. (The whole diagnosis over ranks: tests/mpi.)
#include "kernel/diagnosis/engine.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

using thermnet::detail::pack_refit;
using thermnet::detail::Refit;
using thermnet::detail::unpack_refit;

namespace {

template <class T> bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

} // namespace

TEST_CASE("a refit comes back from its bytes bit for bit") {
  Refit r;
  r.ok = true;
  r.p = {0.1 + 0.2, 1e-300};
  r.se = {std::numeric_limits<double>::quiet_NaN(), 0.25};
  r.sse = 12.000000000000002;
  r.holdout_sse = 0.1 + 0.7;
  r.r = {-0.5f, 0.0f, 3.0f / 7.0f};
  r.holdout_r = {2.0f / 3.0f, -1.0f / 3.0f};
  r.holdout_rho = {0.1 / 3.0};
  const Refit back = unpack_refit(pack_refit(r));
  CHECK(back.ok);
  CHECK(same_bits(back.p, r.p));
  CHECK(same_bits(back.se, r.se));
  CHECK(std::memcmp(&back.sse, &r.sse, sizeof(double)) == 0);
  CHECK(std::memcmp(&back.holdout_sse, &r.holdout_sse, sizeof(double)) == 0);
  CHECK(same_bits(back.r, r.r));
  CHECK(same_bits(back.holdout_r, r.holdout_r));
  CHECK(same_bits(back.holdout_rho, r.holdout_rho));
}

TEST_CASE("a failed refit stays failed, and truncated bytes are an error") {
  Refit failed;
  failed.holdout_r = {1.5f}; // a fold scored before a later fold failed
  const Refit back = unpack_refit(pack_refit(failed));
  CHECK_FALSE(back.ok);
  CHECK(back.p.empty());
  CHECK(same_bits(back.holdout_r, failed.holdout_r));
  const std::string bytes = pack_refit(failed);
  CHECK_THROWS_AS(unpack_refit(std::string_view(bytes).substr(0, bytes.size() - 1)),
                  std::runtime_error);
}
