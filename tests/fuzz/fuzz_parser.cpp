/// libFuzzer target for the language front end: the bytes are a model file, parsed alone and then
/// loaded, linted, instantiated and rendered like `thermnet lint` would, against the element
/// registry, loops and submodels expanded. Any crash, sanitizer report, hang or unbounded memory
/// use is a bug.

#include "kernel/core/element_registry.hpp"
#include "lang/diagnostics.hpp"
#include "lang/model.hpp"
#include "lang/parser.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

using namespace thermnet;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);

  // 1. The parser alone.
  {
    lang::SourceManager sources;
    lang::DiagnosticEngine diags(sources);
    const lang::FileId id = sources.add("fuzz.tnet", text);
    (void)lang::parse_file(id, sources, diags);
    (void)lang::render_text(diags);
  }

  // 2. The whole front end. The model lives in a folder that does not exist, so relative
  // includes and data files fail to open instead of reading whatever lies around.
  lang::SourceManager sources;
  lang::DiagnosticEngine diags(sources);
  // Loops and instances may generate at most 20,000 declarations and iterations here, so that a
  // short input cannot ask for more time or memory than the fuzzer allows.
  lang::LoadOptions options;
  options.max_generated = 20'000;
  auto model = lang::Model::from_text("/nonexistent-thermnet-fuzz/fuzz.tnet", text,
                                      thermnet::element_catalog(), sources, diags, options);
  model->lint(diags);
  diags.sort();
  (void)lang::render_text(diags);
  (void)lang::render_json(diags);
  (void)lang::render_sarif(diags, "fuzz");
  if (diags.error_count() == 0) {
    // A clean model must instantiate every case and report its params without throwing.
    for (const auto& name : model->case_names())
      (void)model->instantiate(name);
    (void)model->params();
  } else {
    for (const auto& name : model->case_names()) {
      try {
        (void)model->instantiate(name);
      } catch (const lang::ModelError&) {
      }
    }
  }
  return 0;
}
