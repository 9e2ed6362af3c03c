// The process group's arithmetic: shares cover an index range exactly once, in rank order, and a
// single process runs every index without exchanging anything. (Several ranks: tests/mpi.)
#include "kernel/core/process_group.hpp"

#include <doctest/doctest.h>

#include <atomic>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
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

namespace {

/// Two processes played by one: this one is `rank`, and all_gather hands back `other` as the
/// other rank's bytes (and keeps what this one sent).
class TwoRanks final : public ProcessGroup {
public:
  TwoRanks(int rank, std::string other) : rank_(rank), other_(std::move(other)) {}
  int rank() const override { return rank_; }
  int size() const override { return 2; }
  std::vector<std::string> all_gather(const std::string& mine) const override {
    sent = mine;
    return rank_ == 0 ? std::vector<std::string>{mine, other_}
                      : std::vector<std::string>{other_, mine};
  }
  mutable std::string sent; ///< what this process sent

private:
  int rank_;
  std::string other_;
};

} // namespace

TEST_CASE("a cancelled share sends only the indices that ran; the others keep their value") {
  // Rank 1 of 2 over [0, 10) owns [5, 10); it is cancelled after running 5, 6 and 7.
  std::atomic<bool> cancel{false};
  std::vector<int> on_1(10, -1);
  auto rank_1 = std::make_unique<TwoRanks>(1, std::string());
  TwoRanks& one = *rank_1;
  set_process_group(std::move(rank_1));
  distributed_for(
      10, 1,
      [&](std::size_t i) {
        on_1[i] = static_cast<int>(10 * i);
        if (i == 7) cancel = true;
      },
      [&](std::size_t i) { return std::to_string(on_1[i]); },
      [&](std::size_t, std::string_view) { FAIL("rank 0 sent nothing"); }, &cancel);
  const std::string from_1 = one.sent;
  // Rank 0 runs all of [0, 5) and receives rank 1's three results; 8 and 9 stay as they were.
  std::vector<int> on_0(10, -1);
  set_process_group(std::make_unique<TwoRanks>(0, from_1));
  distributed_for(
      10, 2, [&](std::size_t i) { on_0[i] = static_cast<int>(10 * i); },
      [&](std::size_t i) { return std::to_string(on_0[i]); },
      [&](std::size_t i, std::string_view bytes) { on_0[i] = std::stoi(std::string(bytes)); });
  set_process_group(nullptr);
  CHECK(on_0 == std::vector<int>{0, 10, 20, 30, 40, 50, 60, 70, -1, -1});
  CHECK(from_1.size() == 3 * (2 * sizeof(std::uint64_t) + 2));
}
