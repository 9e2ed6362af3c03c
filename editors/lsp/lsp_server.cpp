#include "editors/lsp/lsp_server.hpp"

#include "editors/lsp/completion.hpp"
#include "editors/lsp/hover.hpp"
#include "editors/lsp/jsonrpc.hpp"
#include "editors/lsp/lsp_diagnostics.hpp"
#include "editors/lsp/navigation.hpp"
#include "editors/lsp/position.hpp"

#include <exception>

#include <fmt/format.h>

namespace thermnet::lsp {
namespace {

// JSON-RPC and LSP error codes.
constexpr int parse_error = -32700;
constexpr int invalid_request = -32600;
constexpr int method_not_found = -32601;
constexpr int invalid_params = -32602;
constexpr int internal_error = -32603;
constexpr int server_not_initialized = -32002;

/// A request that failed with a protocol error code.
struct RequestError : std::runtime_error {
  RequestError(int c, const std::string& what) : std::runtime_error(what), code(c) {}
  int code;
};

nlohmann::json capabilities() {
  return {
      {"textDocumentSync", {{"openClose", true}, {"change", 1}}}, // 1: full text on change
      {"hoverProvider", true},
      {"completionProvider", {{"triggerCharacters", {".", " ", "="}}}},
      {"definitionProvider", true},
      {"documentSymbolProvider", true},
  };
}

} // namespace

Server::Server(std::istream& in, std::ostream& out, std::ostream& log)
    : in_(in), out_(out), log_(log) {}

int Server::run() {
  while (!exit_) {
    Frame f = read_frame(in_);
    if (f.status == Frame::Status::eof) break;
    if (f.status == Frame::Status::bad_header) {
      log_ << "thermnet lsp: skipped a message with a bad header: " << f.error << "\n";
      respond_error(nullptr, parse_error, "bad message header: " + f.error);
      continue;
    }
    handle(f.body);
  }
  return shutdown_ ? 0 : 1;
}

void Server::handle(const std::string& body) {
  nlohmann::json msg;
  // The parser itself does not recurse; arrays and objects nested too deep are dropped as they
  // are read, and the message refused (with its id, when that was not too deep).
  bool too_deep = false;
  const nlohmann::json::parser_callback_t shallow =
      [&too_deep](int depth, nlohmann::json::parse_event_t event, nlohmann::json&) {
        if (depth < max_json_depth || (event != nlohmann::json::parse_event_t::object_start &&
                                       event != nlohmann::json::parse_event_t::array_start))
          return true;
        too_deep = true;
        return false;
      };
  try {
    msg = nlohmann::json::parse(body, shallow);
  } catch (const nlohmann::json::exception& e) {
    respond_error(nullptr, parse_error, std::string("invalid JSON: ") + e.what());
    return;
  }
  if (too_deep) {
    // The id, when it is one (a string or a number); what is left of a deep one is not.
    nlohmann::json id;
    if (msg.is_object() && msg.contains("id") && (msg["id"].is_string() || msg["id"].is_number()))
      id = msg["id"];
    respond_error(
        id, invalid_request,
        fmt::format("the message nests arrays and objects more than {} deep", max_json_depth));
    return;
  }
  if (!msg.is_object() || !msg.contains("method") || !msg["method"].is_string()) {
    if (msg.is_object() && (msg.contains("result") || msg.contains("error")))
      return; // a response to a request of ours (we send none): ignore
    nlohmann::json id = msg.is_object() && msg.contains("id") ? msg["id"] : nlohmann::json();
    respond_error(id, invalid_request, "not a JSON-RPC request or notification");
    return;
  }
  const std::string method = msg["method"].get<std::string>();
  const nlohmann::json params = msg.value("params", nlohmann::json::object());
  if (msg.contains("id"))
    dispatch_request(msg["id"], method, params);
  else
    dispatch_notification(method, params);
}

void Server::dispatch_request(const nlohmann::json& id, const std::string& method,
                              const nlohmann::json& params) {
  try {
    if (method == "initialize") {
      initialized_ = true;
      respond(id, {{"capabilities", capabilities()},
                   {"serverInfo", {{"name", "thermnet"}, {"version", THERMNET_VERSION}}}});
      return;
    }
    if (!initialized_) throw RequestError(server_not_initialized, "initialize first");
    if (shutdown_) throw RequestError(invalid_request, "the server is shutting down");
    if (method == "textDocument/documentSymbol")
      if (const Document* doc = document(params)) { // one item per declaration: written as text
        respond_text(id, document_symbols_text(*doc));
        return;
      }
    respond(id, request_result(method, params));
  } catch (const RequestError& e) {
    respond_error(id, e.code, e.what());
  } catch (const nlohmann::json::exception& e) {
    respond_error(id, invalid_params, std::string("malformed parameters: ") + e.what());
  } catch (const std::exception& e) {
    respond_error(id, internal_error, e.what());
  }
}

nlohmann::json Server::request_result(const std::string& method, const nlohmann::json& params) {
  if (method == "shutdown") {
    shutdown_ = true;
    return nullptr;
  }
  const bool positional = method == "textDocument/hover" || method == "textDocument/completion" ||
                          method == "textDocument/definition";
  if (positional || method == "textDocument/documentSymbol") {
    const Document* doc = document(params);
    if (!doc) return method == "textDocument/completion" ? nlohmann::json::array() : nullptr;
    std::size_t at = offset_at(doc->text(), position_from_json(params.at("position")));
    if (method == "textDocument/hover") return hover(*doc, at);
    if (method == "textDocument/completion") return completion(*doc, at);
    return definition(*doc, at);
  }
  throw RequestError(method_not_found, "unknown method '" + method + "'");
}

void Server::dispatch_notification(const std::string& method, const nlohmann::json& params) {
  try {
    if (method == "exit") {
      exit_ = true;
    } else if (method == "textDocument/didOpen") {
      const auto& td = params.at("textDocument");
      std::string uri = td.at("uri").get<std::string>();
      auto doc = std::make_unique<Document>(uri, td.at("text").get<std::string>(),
                                            td.value("version", 0L));
      publish(*doc);
      documents_[uri] = std::move(doc);
    } else if (method == "textDocument/didChange") {
      std::string uri = params.at("textDocument").at("uri").get<std::string>();
      auto it = documents_.find(uri);
      const auto& changes = params.at("contentChanges");
      if (it == documents_.end() || changes.empty()) return;
      // Full synchronisation: the last change holds the whole text.
      it->second->update(changes.back().at("text").get<std::string>(),
                         params.at("textDocument").value("version", 0L));
      publish(*it->second);
    } else if (method == "textDocument/didClose") {
      std::string uri = params.at("textDocument").at("uri").get<std::string>();
      documents_.erase(uri);
      send({{"jsonrpc", "2.0"},
            {"method", "textDocument/publishDiagnostics"},
            {"params", {{"uri", uri}, {"diagnostics", nlohmann::json::array()}}}});
    }
    // initialized, $/cancelRequest, $/setTrace, didSave, ...: nothing to do.
  } catch (const std::exception& e) {
    log_ << "thermnet lsp: " << method << ": " << e.what() << "\n";
  }
}

const Document* Server::document(const nlohmann::json& params) const {
  auto it = documents_.find(params.at("textDocument").at("uri").get<std::string>());
  return it == documents_.end() ? nullptr : it->second.get();
}

void Server::publish(const Document& doc) {
  write_frame(out_, publish_diagnostics_message(doc));
}

void Server::respond(const nlohmann::json& id, nlohmann::json result) {
  send({{"jsonrpc", "2.0"}, {"id", id}, {"result", std::move(result)}});
}

void Server::respond_text(const nlohmann::json& id, const std::string& result) {
  std::string message = "{\"id\":";
  message += id.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  message.reserve(message.size() + result.size() + 32);
  message += ",\"jsonrpc\":\"2.0\",\"result\":";
  message += result;
  message += '}';
  write_frame(out_, message);
}

void Server::respond_error(const nlohmann::json& id, int code, const std::string& message) {
  send({{"jsonrpc", "2.0"}, {"id", id}, {"error", {{"code", code}, {"message", message}}}});
}

void Server::send(const nlohmann::json& message) {
  write_frame(out_, message.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

} // namespace thermnet::lsp
