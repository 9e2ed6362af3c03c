#pragma once
/// The command line under mpirun (docs/cluster.md): MPI is started when the process was launched by
/// mpirun, the kernel's process group becomes MPI_COMM_WORLD, ranks other than 0 keep quiet, and
/// a rank that fails ends the whole job with its error instead of leaving the others waiting.
/// Without mpirun, or in a build without MPI, nothing changes.

namespace thermnet::app {

/// MPI for the lifetime of main().
class MpiSession {
public:
  /// Starts MPI when launched by mpirun with several ranks (and the build has MPI).
  MpiSession(int& argc, char**& argv);
  /// Ends MPI if finish() was not called (an exception left main).
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  /// Ends the run with `status`: 0 finalizes MPI; any other status on any rank prints that rank's
  /// messages and aborts the whole job (MPI_Abort) with it. Returns status.
  int finish(int status);

private:
  bool active_ = false;   ///< MPI was started with several ranks
  int rank_ = 0;          ///< this rank
  int size_ = 1;          ///< number of ranks
  int saved_stderr_ = -1; ///< the real stderr of a quiet rank (its own goes to a buffer)
  int captured_ = -1;     ///< the buffer file of a quiet rank's stderr
};

} // namespace thermnet::app
