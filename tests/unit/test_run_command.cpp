// Unit tests of run_command: the one place where a command's exceptions become a message on
// stderr and an exit status (0 ok, 1 input wrong or operation failed, 2 usage or a file that
// cannot be read or written).

#include "app/output_files.hpp"
#include "cli/run_command.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/solver_types.hpp"
#include "kernel/diagnosis/diagnosis.hpp"
#include "kernel/estimation/estimator.hpp"
#include "lang/csv.hpp"
#include "lang/model.hpp"
#include "lang/rewrite/model_files.hpp"

#include <doctest/doctest.h>

#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace {

using namespace thermnet;

/// What a run printed on stderr and the status it returned.
struct Outcome {
  int status = -1;
  std::string err;
};

/// Runs a body that throws `e` through run_command, capturing stderr.
template <typename E> Outcome run_throwing(const E& e, int invalid_argument_status = 1) {
  std::ostringstream captured;
  std::streambuf* old = std::cerr.rdbuf(captured.rdbuf());
  Outcome o;
  try {
    o.status = cli::run_command(
        "thermnet test", [&](lang::SourceManager&) -> int { throw e; }, invalid_argument_status);
  } catch (...) {
    std::cerr.rdbuf(old);
    throw;
  }
  std::cerr.rdbuf(old);
  o.err = captured.str();
  return o;
}

} // namespace

TEST_CASE("run_command: the body's status passes through, and it gets a source manager") {
  std::size_t files = 99;
  CHECK(cli::run_command("thermnet test", [&](lang::SourceManager& s) {
          files = s.size();
          return 1;
        }) == 1);
  CHECK(files == 0);
  CHECK(cli::run_command("thermnet test", [](lang::SourceManager&) { return 0; }) == 0);
}

TEST_CASE("run_command: unwritable outputs and unreadable files are exit 2") {
  Outcome o = run_throwing(app::OutputError("cannot write 'x.csv': No such file or directory"));
  CHECK(o.status == 2);
  CHECK(o.err == "thermnet test: error: cannot write 'x.csv': No such file or directory\n");
  CHECK(run_throwing(rewrite::RewriteError("-o 'a.tnet' would overwrite a file")).status == 2);
  o = run_throwing(lang::CsvError("data.csv", 0, 0, "No such file or directory"));
  CHECK(o.status == 2);
  CHECK(o.err.find("thermnet test: error: data.csv") == 0);
}

TEST_CASE("run_command: wrong input and failed operations are exit 1") {
  CHECK(run_throwing(lang::CsvError("data.csv", 3, 2, "'x' is not a number")).status == 1);
  const Outcome o = run_throwing(SolverError("CVODE failed at t = 5 s", "CVode", -3, 5.0, {}));
  CHECK(o.status == 1);
  CHECK(o.err == "thermnet test: error: CVODE failed at t = 5 s\n");
  CHECK(run_throwing(NetworkError("no such node")).status == 1);
  CHECK(run_throwing(EstimatorError("bad option")).status == 1);
  CHECK(run_throwing(DiagnosisError("no data")).status == 1);
}

TEST_CASE("run_command: std::invalid_argument takes the command's status") {
  CHECK(run_throwing(std::invalid_argument("case 'c' has no data file")).status == 1);
  const Outcome o = run_throwing(std::invalid_argument("--nodes: no node 'x'"), 2);
  CHECK(o.status == 2);
  CHECK(o.err == "thermnet test: error: --nodes: no node 'x'\n");
}

TEST_CASE("run_command: a model error is printed compiler-style; a bad --case is usage") {
  lang::Diagnostic d;
  d.code = "unknown-case";
  d.message = "the model has no case 'nope'";
  d.file_hint = "m.tnet";
  Outcome o = run_throwing(lang::ModelError(d));
  CHECK(o.status == 2);
  CHECK(o.err.find("m.tnet: error: the model has no case 'nope' [unknown-case]") == 0);
  d.code = "bad-value";
  CHECK(run_throwing(lang::ModelError(d)).status == 1);
}

TEST_CASE("run_command: other exceptions are left to main's last-resort handler") {
  CHECK_THROWS_AS(run_throwing(std::runtime_error("unexpected")), std::runtime_error);
}
