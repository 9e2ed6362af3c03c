// MpiSession: MPI_COMM_WORLD as the kernel's process group (all_gather with MPI_Allgatherv), quiet
// ranks, and MPI_Abort on a failure so no rank waits forever for one that stopped.

#include "cli/mpi_session.hpp"

#include "kernel/core/process_group.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>

#include <fcntl.h>
#include <unistd.h>

#ifdef THERMNET_WITH_MPI
#include <mpi.h>
#endif

namespace thermnet::cli {
namespace {

#ifdef THERMNET_WITH_MPI
/// True when an MPI launcher (OpenMPI's mpirun, or a PMI-based one such as srun) started us.
bool launched_by_mpirun() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"})
    if (std::getenv(var)) return true;
  return false;
}

/// Writes all of a string to a file descriptor.
void write_all(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

/// MPI_COMM_WORLD.
class MpiWorld final : public ProcessGroup {
public:
  MpiWorld(int rank, int size) : rank_(rank), size_(size) {}
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  std::vector<std::string> all_gather(const std::string& mine) const override {
    const auto p = static_cast<std::size_t>(size_);
    std::int64_t length = static_cast<std::int64_t>(mine.size());
    std::vector<std::int64_t> lengths(p);
    MPI_Allgather(&length, 1, MPI_INT64_T, lengths.data(), 1, MPI_INT64_T, MPI_COMM_WORLD);
    std::vector<int> counts(p), displs(p);
    std::int64_t total = 0;
    for (std::size_t r = 0; r < p; ++r) {
      if (total + lengths[r] > std::numeric_limits<int>::max())
        throw std::runtime_error(fmt::format(
            "the results of the {} ranks exceed 2 GiB; use fewer samples per run", size_));
      displs[r] = static_cast<int>(total);
      counts[r] = static_cast<int>(lengths[r]);
      total += lengths[r];
    }
    std::string all(static_cast<std::size_t>(total), '\0');
    MPI_Allgatherv(mine.data(), counts[static_cast<std::size_t>(rank_)], MPI_CHAR, all.data(),
                   counts.data(), displs.data(), MPI_CHAR, MPI_COMM_WORLD);
    std::vector<std::string> out(p);
    for (std::size_t r = 0; r < p; ++r)
      out[r] = all.substr(static_cast<std::size_t>(displs[r]), static_cast<std::size_t>(counts[r]));
    return out;
  }

private:
  int rank_, size_;
};
#endif

} // namespace

MpiSession::MpiSession([[maybe_unused]] int& argc, [[maybe_unused]] char**& argv) {
#ifdef THERMNET_WITH_MPI
  if (!launched_by_mpirun()) return;
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  active_ = true;
  if (size_ == 1) return;
  set_process_group(std::make_unique<MpiWorld>(rank_, size_));
  if (rank_ == 0) return;
  // Quiet ranks: their standard output is rank 0's; their stderr is kept aside and shown only if
  // the rank fails.
  std::fflush(stdout);
  std::fflush(stderr);
  const int null = ::open("/dev/null", O_WRONLY);
  if (null >= 0) {
    ::dup2(null, STDOUT_FILENO);
    ::close(null);
  }
  if (std::FILE* buffer = std::tmpfile()) {
    captured_ = ::dup(::fileno(buffer));
    saved_stderr_ = ::dup(STDERR_FILENO);
    ::dup2(captured_, STDERR_FILENO);
  }
#endif
}

MpiSession::~MpiSession() {
  if (active_) finish(0);
}

int MpiSession::finish(int status) {
  if (!active_) return status;
  active_ = false;
#ifdef THERMNET_WITH_MPI
  if (status != 0 && size_ > 1) {
    std::fflush(stderr);
    std::string text;
    if (captured_ >= 0) {
      // Replay the rank's own messages on the real stderr, each line marked with the rank.
      ::lseek(captured_, 0, SEEK_SET);
      char chunk[4096];
      for (ssize_t n; (n = ::read(captured_, chunk, sizeof chunk)) > 0;)
        text.append(chunk, static_cast<std::size_t>(n));
      std::string marked;
      std::size_t start = 0;
      while (start < text.size()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size() - 1;
        marked += fmt::format("[rank {}] {}", rank_, text.substr(start, end - start + 1));
        start = end + 1;
      }
      text = marked;
    }
    text += fmt::format("thermnet: rank {} of {} failed (exit status {}); ending the job\n", rank_,
                        size_, status);
    write_all(saved_stderr_ >= 0 ? saved_stderr_ : STDERR_FILENO, text);
    MPI_Abort(MPI_COMM_WORLD, status);
  }
  MPI_Finalize();
#endif
  return status;
}

} // namespace thermnet::cli
