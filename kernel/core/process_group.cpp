// The process group: the single-process default, the share arithmetic and distributed_for().

#include "kernel/core/process_group.hpp"

#include "kernel/core/parallel.hpp"

#include <stdexcept>
#include <vector>

namespace thermnet {
namespace {

/// One process: nothing to exchange.
class SingleProcess final : public ProcessGroup {
public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  std::vector<std::string> all_gather(const std::string& mine) const override { return {mine}; }
};

std::unique_ptr<ProcessGroup>& installed() {
  static std::unique_ptr<ProcessGroup> group = std::make_unique<SingleProcess>();
  return group;
}

} // namespace

const ProcessGroup& process_group() {
  return *installed();
}

void set_process_group(std::unique_ptr<ProcessGroup> group) {
  installed() = group ? std::move(group) : std::make_unique<SingleProcess>();
}

std::pair<std::size_t, std::size_t> share_of(std::size_t n, int rank, int size) {
  const auto p = static_cast<std::size_t>(size), r = static_cast<std::size_t>(rank);
  const std::size_t base = n / p, extra = n % p;
  const std::size_t begin = r * base + std::min(r, extra);
  return {begin, begin + base + (r < extra ? 1 : 0)};
}

void throw_short_buffer() {
  throw std::runtime_error("a result received from another process is truncated");
}

void distributed_for(std::size_t n, int threads, const std::function<void(std::size_t)>& body,
                     const std::function<std::string(std::size_t)>& pack,
                     const std::function<void(std::size_t, std::string_view)>& unpack,
                     const std::atomic<bool>* cancel) {
  const ProcessGroup& group = process_group();
  const auto [begin, end] = share_of(n, group.rank(), group.size());
  // Which indices ran (all of them unless cancelled): only those travel, so that a cancelled run
  // of millions of indices exchanges what it did, not its whole share.
  std::vector<char> ran(end - begin, 0);
  parallel_for(
      end - begin, threads,
      [&, begin = begin](std::size_t k) {
        body(begin + k);
        ran[k] = 1;
      },
      cancel);
  if (group.size() == 1) return;
  // Each result travels as its index, its length and its bytes, in index order.
  std::string mine;
  for (std::size_t i = begin; i < end; ++i) {
    if (!ran[i - begin]) continue;
    const std::string bytes = pack(i);
    append_bytes(mine, static_cast<std::uint64_t>(i));
    append_bytes(mine, static_cast<std::uint64_t>(bytes.size()));
    mine += bytes;
  }
  const std::vector<std::string> all = group.all_gather(mine);
  for (int r = 0; r < group.size(); ++r) {
    if (r == group.rank()) continue;
    const auto [b, e] = share_of(n, r, group.size());
    std::string_view in(all[static_cast<std::size_t>(r)]);
    while (!in.empty()) {
      const auto i = take_bytes<std::uint64_t>(in);
      const auto length = take_bytes<std::uint64_t>(in);
      if (i < b || i >= e || in.size() < length) throw_short_buffer();
      unpack(i, in.substr(0, length));
      in.remove_prefix(length);
    }
  }
}

} // namespace thermnet
