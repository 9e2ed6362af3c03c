#pragma once
/// Work spread over processes (MPI ranks, docs/cluster.md) as well as threads: each process runs a
/// contiguous share of an index range, then the shares are exchanged so every process holds every
/// result, in index order. A single process (the default) runs the whole range.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace thermnet {

/// The processes a run is spread over.
class ProcessGroup {
public:
  virtual ~ProcessGroup() = default;
  /// This process's index, 0 .. size() - 1.
  virtual int rank() const = 0;
  /// Number of processes.
  virtual int size() const = 0;
  /// Every process passes its bytes; every process gets all of them, in rank order (collective:
  /// every process must call it, in the same order as every other collective).
  virtual std::vector<std::string> all_gather(const std::string& mine) const = 0;
};

/// The group runs are spread over: a single process unless set_process_group() installed another.
const ProcessGroup& process_group();

/// Installs the group (the command line does, under mpirun); nullptr restores the single process.
void set_process_group(std::unique_ptr<ProcessGroup> group);

/// The share [begin, end) of n indices that process `rank` of `size` runs: contiguous blocks in
/// rank order, sizes differing by at most one.
std::pair<std::size_t, std::size_t> share_of(std::size_t n, int rank, int size);

/// Runs body(i) for this process's share of [0, n) on `threads` workers (parallel_for), then, with
/// several processes, gives every process the results of the others: pack(i) serialises result i
/// where it was computed and unpack(i, bytes) restores it everywhere else. With results stored
/// by index, the outcome is the same whatever the number of processes and threads. Indices that a
/// `cancel` skipped are not sent: they keep their value on every process.
void distributed_for(std::size_t n, int threads, const std::function<void(std::size_t)>& body,
                     const std::function<std::string(std::size_t)>& pack,
                     const std::function<void(std::size_t, std::string_view)>& unpack,
                     const std::atomic<bool>* cancel = nullptr);

/// Throws the error of a result buffer that ends too early (take_bytes).
[[noreturn]] void throw_short_buffer();

/// Appends the bytes of a trivially copyable value to a buffer.
template <typename T> void append_bytes(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

/// Reads a trivially copyable value from the front of a buffer and advances it; throws
/// std::runtime_error when the buffer is too short.
template <typename T> T take_bytes(std::string_view& in) {
  T value{};
  if (in.size() < sizeof(T)) throw_short_buffer();
  std::memcpy(&value, in.data(), sizeof(T));
  in.remove_prefix(sizeof(T));
  return value;
}

/// Appends a vector of trivially copyable values to a buffer: its length, then its elements.
template <typename T> void append_values(std::string& out, const std::vector<T>& values) {
  static_assert(std::is_trivially_copyable_v<T>);
  append_bytes(out, static_cast<std::uint64_t>(values.size()));
  if (!values.empty())
    out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

/// Reads a vector that append_values() wrote from the front of a buffer and advances it; throws
/// std::runtime_error when the buffer is too short.
template <typename T> std::vector<T> take_values(std::string_view& in) {
  static_assert(std::is_trivially_copyable_v<T>);
  const auto n = take_bytes<std::uint64_t>(in);
  if (n > in.size() / sizeof(T)) throw_short_buffer();
  std::vector<T> values(static_cast<std::size_t>(n));
  if (!values.empty()) std::memcpy(values.data(), in.data(), values.size() * sizeof(T));
  in.remove_prefix(values.size() * sizeof(T));
  return values;
}

} // namespace thermnet
