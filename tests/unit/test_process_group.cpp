// The process group's arithmetic: shares cover an index range exactly once, in rank order, and a
// single process runs every index without exchanging anything. (Several ranks: tests/mpi.)
#include "kernel/core/process_group.hpp"

#include <doctest/doctest.h>

#include <cstring>
#include <limits>
#include <vector>

using namespace thermnet;

TEST_CASE("shares are contiguous, in rank order, cover the range once and differ by at most one") {
  for (std::size_t n : {0u, 1u, 2u, 7u, 12000u, 12001u})
    for (int size : {1, 2, 3, 4, 7}) {
      std::size_t next = 0, smallest = n, largest = 0;
      for (int r = 0; r < size; ++r) {
        const auto [b, e] = share_of(n, r, size);
        CHECK(b == next);
        CHECK(e >= b);
        smallest = std::min(smallest, e - b);
        largest = std::max(largest, e - b);
        next = e;
      }
      CHECK(next == n);
      CHECK(largest - smallest <= 1);
    }
}

TEST_CASE("a single process runs every index and unpacks nothing") {
  REQUIRE(process_group().size() == 1);
  std::vector<int> ran(50, 0);
  int unpacked = 0;
  distributed_for(
      ran.size(), 3, [&](std::size_t i) { ran[i] += 1; },
      [&](std::size_t i) { return std::to_string(i); },
      [&](std::size_t, std::string_view) { ++unpacked; });
  CHECK(std::vector<int>(50, 1) == ran);
  CHECK(unpacked == 0);
}

TEST_CASE("values travel through bytes unchanged, and a short buffer is an error") {
  std::string buffer;
  append_bytes(buffer, 0.1 + 0.2);
  append_bytes(buffer, std::uint64_t{42});
  std::string_view in(buffer);
  CHECK(take_bytes<double>(in) == 0.1 + 0.2);
  CHECK(take_bytes<std::uint64_t>(in) == 42);
  CHECK(in.empty());
  CHECK_THROWS_AS(take_bytes<double>(in), std::runtime_error);
}

TEST_CASE("vectors travel through bytes unchanged, empty ones too; a short buffer is an error") {
  const std::vector<double> values{1.0 / 3.0, -0.0, std::numeric_limits<double>::quiet_NaN(),
                                   1e300};
  std::string buffer;
  append_values(buffer, values);
  append_values(buffer, std::vector<double>{});
  append_bytes(buffer, 7);
  std::string_view in(buffer);
  const auto back = take_values<double>(in);
  REQUIRE(back.size() == values.size());
  CHECK(std::memcmp(back.data(), values.data(), values.size() * sizeof(double)) == 0);
  CHECK(take_values<double>(in).empty());
  CHECK(take_bytes<int>(in) == 7);
  CHECK(in.empty());
  std::string_view cut(buffer.data(), buffer.size() / 2);
  CHECK_THROWS_AS(take_values<double>(cut), std::runtime_error);
}
