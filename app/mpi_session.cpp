// MpiSession: MPI_COMM_WORLD as the kernel's process group (all_gather with MPI_Allgatherv), quiet
// ranks, and MPI_Abort on a failure so no rank waits forever for one that stopped.

#include "app/mpi_session.hpp"

#include "kernel/core/process_group.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#ifdef THERMNET_WITH_MPI
#include <mpi.h>
#endif

namespace thermnet::app {
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

/// How long a rank that failed waits for the others to end too before it aborts the job, s.
constexpr double kAgreementWait = 10.0;

/// Each line of `text` marked with the rank: "[rank R] ...".
std::string marked(const std::string& text, int rank) {
  std::string out;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size() - 1;
    out += fmt::format("[rank {}] {}", rank, text.substr(start, end - start + 1));
    start = end + 1;
  }
  if (!out.empty() && out.back() != '\n') out += '\n';
  return out;
}

/// A duplicate of MPI_COMM_WORLD on which the ranks agree how the job ends.
MPI_Comm& ending_comm() {
  static MPI_Comm comm = MPI_COMM_NULL;
  return comm;
}

/// What a quiet rank wrote on its stderr (kept in the file `fd`; empty for rank 0).
std::string captured_text(int fd) {
  std::string text;
  if (fd < 0) return text;
  ::lseek(fd, 0, SEEK_SET);
  char chunk[4096];
  for (ssize_t n; (n = ::read(fd, chunk, sizeof chunk)) > 0;)
    text.append(chunk, static_cast<std::size_t>(n));
  return text;
}

/// Gathers every rank's exit status into `out`; waits at most `wait_s` seconds (forever when
/// negative) for the other ranks to arrive. False when they did not.
bool all_statuses(MPI_Comm comm, int status, double wait_s, int size, std::vector<int>& out) {
  out.assign(static_cast<std::size_t>(size), 0);
  MPI_Request request = MPI_REQUEST_NULL;
  MPI_Iallgather(&status, 1, MPI_INT, out.data(), 1, MPI_INT, comm, &request);
  if (wait_s < 0) {
    MPI_Wait(&request, MPI_STATUS_IGNORE);
    return true;
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(wait_s);
  for (;;) {
    int done = 0;
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) return true;
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

/// With every rank at the end and one of them failed: rank 0, which printed its own messages as
/// they came, prints those of the quiet ranks that failed, each distinct text once, marked with
/// its rank. When rank 0 failed too, and every quiet rank that failed did so with rank 0's status
/// and the same words, the error was the same everywhere (the ranks read the same model and
/// options): it was printed once already.
void report_failures(MPI_Comm comm, int rank, const std::vector<int>& statuses,
                     const std::string& mine) {
  const int length = static_cast<int>(mine.size());
  std::vector<int> lengths(statuses.size()), offsets(statuses.size());
  MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, comm);
  std::string all;
  if (rank == 0)
    for (std::size_t r = 0; r < lengths.size(); ++r) {
      offsets[r] = static_cast<int>(all.size());
      all.append(static_cast<std::size_t>(lengths[r]), '\0');
    }
  MPI_Gatherv(mine.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR,
              0, comm);
  if (rank != 0) return;
  std::vector<std::pair<std::size_t, std::string>> failed;
  for (std::size_t r = 1; r < statuses.size(); ++r)
    if (statuses[r] != 0)
      failed.emplace_back(r, all.substr(static_cast<std::size_t>(offsets[r]),
                                        static_cast<std::size_t>(lengths[r])));
  const bool as_rank_0 =
      statuses[0] != 0 && std::all_of(failed.begin(), failed.end(), [&](const auto& f) {
        return statuses[f.first] == statuses[0] && f.second == failed.front().second;
      });
  if (as_rank_0) return;
  std::vector<std::string> shown;
  for (const auto& [r, text] : failed) {
    if (std::find(shown.begin(), shown.end(), text) != shown.end()) continue;
    shown.push_back(text);
    write_all(STDERR_FILENO, marked(text, static_cast<int>(r)) +
                                 fmt::format("thermnet: rank {} of {} failed (exit status {})\n", r,
                                             statuses.size(), statuses[r]));
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
  MPI_Comm_dup(MPI_COMM_WORLD, &ending_comm());
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
  if (size_ > 1) {
    std::fflush(stderr);
    const std::string mine = captured_text(captured_);
    // Every rank tells how it ends, on a communicator of its own (a rank still computing waits in
    // collectives on MPI_COMM_WORLD, which this cannot disturb). A rank that failed waits a while
    // for the others: when all arrive, the job ends together and each distinct error is printed
    // once; when one does not, the failed rank ends the job.
    std::vector<int> statuses;
    if (!all_statuses(ending_comm(), status, status == 0 ? -1.0 : kAgreementWait, size_,
                      statuses)) {
      write_all(saved_stderr_ >= 0 ? saved_stderr_ : STDERR_FILENO,
                marked(mine, rank_) +
                    fmt::format("thermnet: rank {} of {} failed (exit status {}); ending the job\n",
                                rank_, size_, status));
      MPI_Abort(MPI_COMM_WORLD, status);
    }
    if (*std::max_element(statuses.begin(), statuses.end()) != 0)
      report_failures(ending_comm(), rank_, statuses, mine);
    MPI_Comm_free(&ending_comm());
  }
  MPI_Finalize();
#endif
  return status;
}

} // namespace thermnet::app
