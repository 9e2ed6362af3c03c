// thermnet: one executable, subcommands listed in README.md (cli/app.hpp). It sets up the heap,
// MPI and standard output around the command line.

#include "app/huge_page_heap.hpp"
#include "app/mpi_session.hpp"
#include "app/output_stream.hpp"
#include "cli/app.hpp"

#include <cstddef>

int main(int argc, char** argv) {
  thermnet::app::reserve_huge_page_heap(std::size_t{1} << 30);
  // Under mpirun the ranks share the work; a rank that fails ends the job (app/mpi_session.hpp).
  thermnet::app::MpiSession mpi(argc, argv);
  thermnet::app::route_standard_output();
  return mpi.finish(thermnet::cli::run_app(argc, argv));
}
