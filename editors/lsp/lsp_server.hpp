#pragma once
/// The thermnet language server: JSON-RPC requests and notifications over a pair of streams.

#include "editors/lsp/document.hpp"

#include <nlohmann/json.hpp>

#include <istream>
#include <map>
#include <memory>
#include <ostream>
#include <string>

namespace thermnet::lsp {

/// Serves one client: initialize/shutdown/exit, document synchronisation (full) with diagnostics,
/// hover, completion, definition and document symbols.
class Server {
public:
  /// A server reading framed messages from `in` and writing to `out`; `log` gets diagnostics of
  /// the server itself (stderr).
  Server(std::istream& in, std::ostream& out, std::ostream& log);
  /// Serves until `exit` or the end of input; returns 0 after a shutdown request, else 1.
  int run();

private:
  void handle(const std::string& body);
  void dispatch_request(const nlohmann::json& id, const std::string& method,
                        const nlohmann::json& params);
  void dispatch_notification(const std::string& method, const nlohmann::json& params);
  nlohmann::json request_result(const std::string& method, const nlohmann::json& params);
  const Document* document(const nlohmann::json& params) const;
  void publish(const Document& doc);
  void respond(const nlohmann::json& id, nlohmann::json result);
  void respond_text(const nlohmann::json& id, const std::string& result);
  void respond_error(const nlohmann::json& id, int code, const std::string& message);
  void send(const nlohmann::json& message);

  std::istream& in_;
  std::ostream& out_;
  std::ostream& log_;
  bool initialized_ = false;
  bool shutdown_ = false;
  bool exit_ = false;
  std::map<std::string, std::unique_ptr<Document>> documents_;
};

} // namespace thermnet::lsp
