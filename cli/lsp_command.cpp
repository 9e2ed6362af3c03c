#include "cli/lsp_command.hpp"

#include "cli/run_command.hpp"
#include "editors/lsp/lsp_server.hpp"

#include <iostream>
#include <memory>

namespace thermnet::cli {

void add_lsp_command(CLI::App& app, int& status) {
  CLI::App* cmd = app.add_subcommand(
      "lsp", "Run the language server (JSON-RPC over standard input and output)");
  // Language clients may pass these; the server always speaks over stdio.
  auto stdio = std::make_shared<bool>(false);
  auto pid = std::make_shared<long>(0);
  cmd->add_flag("--stdio", *stdio,
                "use standard input and output (the default and only transport)");
  cmd->add_option("--clientProcessId", *pid, "process id of the client (ignored)");
  cmd->callback([&status, stdio, pid] {
    status = run_command("thermnet lsp", [](lang::SourceManager&) {
      std::ios::sync_with_stdio(false);
      std::cin.tie(nullptr);
      lsp::Server server(std::cin, std::cout, std::cerr);
      return server.run();
    });
  });
}

} // namespace thermnet::cli
