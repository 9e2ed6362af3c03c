/// libFuzzer target for the language front end: the bytes are a model file, parsed alone and then
/// loaded, linted, instantiated and rendered like `thermnet lint` would, against the element
/// registry, loops and submodels expanded, and every value of an instantiated case evaluated at a
/// few times. Any crash, sanitizer report, hang or unbounded memory use is a bug.
///
/// The model lives in a folder of its own made at start-up, which holds small data files under the
/// names the seed models read (the first rows of the CSV files of models/ and tests/golden, at
/// their paths relative to their model's folder: `statespace.csv`, `data/case01.csv`) and in the
/// layouts campaigns record (UNIX and ISO time stamps, `;` and tab separators, hours, on/off
/// words), so that `data` statements with column maps and `table(data, ...)` reach the files
/// instead of stopping at a missing one. Only that folder may be read (as for the CLI).

#include "kernel/core/element_registry.hpp"
#include "lang/diagnostics.hpp"
#include "lang/model.hpp"
#include "lang/parser.hpp"
#include "lang/path_policy.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

using namespace thermnet;

namespace {

namespace fs = std::filesystem;

std::string folder; // the model's folder, made by LLVMFuzzerInitialize

/// Writes a data file of the model's folder unless the project's files gave it already.
void write(const std::string& name, const std::string& text) {
  if (!fs::exists(folder + "/" + name))
    std::ofstream(folder + "/" + name, std::ios::binary) << text;
}

/// Copies the first 40 lines of each CSV file under `dir` into the model's folder, at its path
/// relative to `dir` without the first `skip` parts (a model's folder under models/).
void copy_heads(const fs::path& dir, int skip) {
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::end(it);
       it.increment(ec)) {
    if (it->path().extension() != ".csv") continue;
    fs::path rel;
    int part = 0;
    for (const auto& p : fs::relative(it->path(), dir, ec))
      if (part++ >= skip) rel /= p;
    if (rel.empty()) continue;
    fs::create_directories((fs::path(folder) / rel).parent_path(), ec);
    std::ifstream in(it->path(), std::ios::binary);
    std::ofstream out(fs::path(folder) / rel, std::ios::binary);
    std::string line;
    for (int n = 0; n < 40 && std::getline(in, line); ++n)
      out << line << '\n';
  }
}

/// The data files of the model's folder.
void write_data_files() {
#ifdef THERMNET_FUZZ_ROOT
  copy_heads(THERMNET_FUZZ_ROOT "/models", 1);
  copy_heads(THERMNET_FUZZ_ROOT "/tests/golden", 0);
#endif
  // The incubator's files: UNIX seconds (and nanoseconds), True/False columns, two air sensors.
  const std::string incubator_s = "time,execution_interval,heater_on,fan_on,t1,t2,t3\n"
                                  "1600356388.8088953,3,False,False,23.5,34.875,34.062\n"
                                  "1600356391.768922,3,True,False,23.5,34.812,34.0\n"
                                  "1600356394.7,3,True,True,23.6,35.1,34.2\n"
                                  "1600356397.9,3,False,True,,35.3,34.4\n"
                                  "1600356400.1,3,False,False,23.6,nan,34.3\n";
  write("random_on_off_sequences_1.csv", incubator_s);
  write("ramp_up_cool_down.csv", incubator_s);
  write("run.csv", incubator_s);
  write("lid_opening_experiment_jan_2021.csv", "time,heater_on,fan_on,lid_open,t1,t2,t3\n"
                                               "1611326938000000000,on,off,no,21.0,30.1,29.9\n"
                                               "1611326941000000000,off,on,yes,21.0,30.0,29.8\n"
                                               "1611326944000000000,on,on,yes,21.1,29.9,29.7\n");
  // A test house: `Time` in seconds, inputs and the indoor temperature in one file.
  write("statespace.csv", "Time,To,Qh,I_sol,xi\n"
                          "0.0,16.23,0.0,13.8,30.28\n"
                          "1800.0,15.83,0.0,13.8,30.20\n"
                          "3600.0,15.5,1000.0,0.0,30.1\n"
                          "5400.0,15.2,1000.0,120.5,30.6\n");
  // FlexHouse style: hours, `;`; ISO dates; tabs; minutes with the time column last.
  write("flexhouse.csv", "t;Ta;Ps;Ph;yTi\n0;5.1;0.2;1;20.5\n0.25;5.0;0.3;0;20.4\n"
                         "0.5;4.9;0.1;1;20.6\n");
  write("iso.csv", "when,T,on\n2021-01-22T14:48:58.7Z,20,on\n2021-01-22 14:58,21,off\n"
                   "2021-01-22T16:08:00+01:00,22,on\n2021-01-22T17:08:00+01:00,22.5,off\n");
  write("tab.csv", "time\ta\tb\n0\t1\t2\n60\t2\t3\n120\t3\tyes\n");
  write("minutes.csv", "a,b,minute\n1,2,0\n2,3,1.5\n3,4,3\n");
  write("weather.csv", "Time;To;I_sol\n1600356388;10;0\n1600360000;11;200\n1600363600;12;400\n");
  write("data.csv", "time,a,b,c\n0,20,21,22\n10,21,22,23\n20,22,23,24\n");
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::string pattern = (fs::temp_directory_path() / "thermnet-fuzz.XXXXXX").string();
  if (!mkdtemp(pattern.data())) std::abort();
  folder = pattern;
  std::atexit([] {
    std::error_code ec;
    fs::remove_all(folder, ec);
  });
  write_data_files();
  // Files outside the model's folder are refused, as for any model the CLI reads.
  lang::set_path_policy(lang::policy_for_model(folder + "/fuzz.tnet"));
  return 0;
}

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

  // 2. The whole front end, in the folder of data files.
  lang::SourceManager sources;
  lang::DiagnosticEngine diags(sources);
  // Loops and instances may generate at most 20,000 declarations and iterations here, and the
  // loops of a case run as often, so that a short input cannot ask for more time or memory than
  // the fuzzer allows.
  lang::LoadOptions options;
  options.max_generated = 20'000;
  options.max_case_iterations = 20'000;
  auto model = lang::Model::from_text(folder + "/fuzz.tnet", text, thermnet::element_catalog(),
                                      sources, diags, options);
  model->lint(diags);
  diags.sort();
  (void)lang::render_text(diags);
  (void)lang::render_json(diags);
  (void)lang::render_sarif(diags, "fuzz");
  const bool clean = diags.error_count() == 0;
  for (const auto& name : model->case_names()) {
    lang::NetworkSpec net;
    try {
      net = model->instantiate(name);
    } catch (const lang::ModelError&) {
      if (clean) std::abort(); // a clean model must instantiate every case
      continue;
    }
    // Every value that may change over time, at a few times (tables, held columns, signals in
    // expressions and the keys they read).
    for (double t : {-1.0, 0.0, 0.5, 1800.0, 1e9}) {
      for (const auto& n : net.nodes)
        (void)n.T.at(t);
      for (const auto& e : net.elements)
        for (const auto& [key, value] : e.values)
          (void)value.at(t);
    }
  }
  if (clean) (void)model->params(); // and report its params
  return 0;
}
