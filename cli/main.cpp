// thermnet: one executable, subcommands listed in README.md (cli/app.hpp). It sets up the heap,
// MPI and standard output around the command line.

#include "cli/app.hpp"
#include "cli/huge_page_heap.hpp"
#include "cli/mpi_session.hpp"
#include "cli/output_stream.hpp"

#include <cstddef>

int main(int argc, char** argv) {
  thermnet::cli::reserve_huge_page_heap(std::size_t{1} << 30);
  // Under mpirun the ranks share the work; a rank that fails ends the job (cli/mpi_session.hpp).
  thermnet::cli::MpiSession mpi(argc, argv);
  thermnet::cli::route_standard_output();
  return mpi.finish(thermnet::cli::run_app(argc, argv));
}
