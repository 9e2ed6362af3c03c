#include "import/importer.hpp"

#include "import/input_files.hpp"
#include "import/report.hpp"
#include "import/sinda_deck.hpp"
#include "import/sinda_network.hpp"
#include "import/spice_network.hpp"
#include "import/tnet_writer.hpp"
#include "lang/display_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <vector>

namespace thermnet::importer {

namespace {

bool starts_with_ci(std::string_view line, std::string_view word) {
  if (line.size() < word.size()) return false;
  for (std::size_t i = 0; i < word.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(line[i])) != word[i]) return false;
  return true;
}

/// Whether a line is a SPICE card: a dot directive thermnet knows, or an element line.
bool spice_card(std::string_view line) {
  static constexpr const char* directives[] = {
      ".subckt", ".ends",   ".param", ".include", ".inc",    ".tran",    ".end",
      ".ic",     ".option", ".model", ".lib",     ".global", ".control", ".temp",
      ".op",     ".print",  ".probe", ".save",    ".meas",   ".func",    ".nodeset"};
  for (const char* d : directives)
    if (starts_with_ci(line, d)) return true;
  if (line.empty()) return false;
  const char c = static_cast<char>(std::tolower(static_cast<unsigned char>(line[0])));
  if (c != 'r' && c != 'c' && c != 'i' && c != 'v' && c != 'x') return false;
  // NAME NODE NODE ...: at least three words.
  int words = 0;
  bool in_word = false;
  for (const char ch : line) {
    const bool blank = ch == ' ' || ch == '\t';
    if (!blank && !in_word) ++words;
    in_word = !blank;
  }
  return words >= 3;
}

} // namespace

Format detect_format(std::string_view text) {
  std::size_t start = 0;
  int spice_lines = 0;
  for (int n = 0; start < text.size() && n < 100000; ++n) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(start, end - start);
    start = end + 1;
    if (starts_with_ci(line, "header") && line.size() > 6 && (line[6] == ' ' || line[6] == '\t'))
      return Format::sinda;
    if (n > 0 && spice_card(line)) ++spice_lines; // line 1 of a netlist is its title
    if (spice_lines >= 2) return Format::spice;
  }
  return spice_lines > 0 ? Format::spice : Format::automatic;
}

const char* format_name(Format f) {
  switch (f) {
  case Format::sinda:
    return "sinda";
  case Format::spice:
    return "spice";
  case Format::automatic:
    return "automatic";
  }
  return "automatic";
}

namespace {

/// The format of the files: the one told, else the first file's that can tell (all must agree).
Format choose_format(const std::vector<std::string>& paths, Format told,
                     lang::SourceManager& sources, Report& report, bool& unreadable) {
  if (told != Format::automatic) return told;
  Format chosen = Format::automatic;
  std::string chosen_by;
  for (const auto& path : paths) {
    lang::FileId id = 0;
    try {
      id = read_input(path, sources);
    } catch (const InputFileError& e) {
      report.file_error(path, e.unreadable ? "file-unreadable" : "invalid-encoding", e.what());
      unreadable = unreadable || e.unreadable;
      return Format::automatic;
    }
    const Format f = detect_format(sources.text(id));
    if (f == Format::automatic) continue;
    if (chosen != Format::automatic && f != chosen) {
      report.file_error(path, "unknown-format",
                        fmt::format("'{}' looks like a {} file, but '{}' like a {} file; import "
                                    "files of one format at a time",
                                    lang::escape_for_display(path), format_name(f),
                                    lang::escape_for_display(chosen_by), format_name(chosen)));
      return Format::automatic;
    }
    chosen = f;
    chosen_by = path;
  }
  if (chosen == Format::automatic)
    report.file_error(paths.front(), "unknown-format",
                      fmt::format("cannot tell the format of '{}' (no HEADER line of a SINDA "
                                  "deck, no SPICE cards): give --format sinda or --format spice",
                                  lang::escape_for_display(paths.front())));
  return chosen;
}

bool reports_unreadable(const lang::DiagnosticEngine& diags) {
  return std::any_of(diags.all().begin(), diags.all().end(), [](const lang::Diagnostic& d) {
    return d.severity == lang::Severity::error &&
           (d.code == "file-unreadable" || d.code == "include-unreadable");
  });
}

} // namespace

ImportResult import_files(const std::vector<std::string>& paths, const ImportOptions& options,
                          lang::DiagnosticEngine& diags, lang::SourceManager& sources) {
  ImportResult result;
  Report report(diags);
  result.format = choose_format(paths, options.format, sources, report, result.unreadable);
  Network net;
  if (result.format == Format::sinda) {
    sinda::Deck deck = sinda::read_deck(paths, sources, report);
    result.files_read = deck.files;
    if (report.error_count() == 0) net = sinda::deck_network(deck, report);
  } else if (result.format == Format::spice) {
    const auto core_kind = [](const std::string& n) {
      static constexpr const char* kinds[] = {
          "conductance", "resistor",   "conduction", "cylinder_conduction",
          "contact",     "convection", "radiation",  "switched_conductance",
          "heater",      "thermostat", "sensor"};
      return std::any_of(std::begin(kinds), std::end(kinds), [&](const char* k) { return n == k; });
    };
    net = spice::read_network(paths, sources, report, result.files_read,
                              options.is_kind ? options.is_kind : core_kind);
  }
  result.unreadable = result.unreadable || reports_unreadable(diags);
  result.dropped = report.dropped_count();
  result.failed = report.error_count() > 0 || result.format == Format::automatic ||
                  (result.dropped > 0 && !options.allow_partial);
  if (result.failed) return result;
  if (result.format == Format::sinda)
    note_floating(net, report, [](const Name& n) { return n.text(); });
  const Counts counts = net.expanded ? *net.expanded
                                     : Counts{net.nodes.size(), net.boundaries.size(),
                                              net.links.size(), net.heaters.size()};
  result.nodes = counts.nodes;
  result.boundaries = counts.boundaries;
  result.links = counts.links;
  result.heaters = counts.heaters;
  result.text = write_tnet(net, report.remarks(), sources);
  return result;
}

} // namespace thermnet::importer
