#include "cli/model_loading.hpp"

#include "kernel/element_registry.hpp"

#include <cstdlib>
#include <unistd.h>

namespace thermnet::cli {

std::unique_ptr<lang::Model> load_model(const std::string& path, lang::SourceManager& sources,
                                        lang::DiagnosticEngine& diags) {
  return lang::Model::load(path, ElementRegistry::global(), sources, diags);
}

bool use_color(int fd) { return ::isatty(fd) && std::getenv("NO_COLOR") == nullptr; }

} // namespace thermnet::cli
