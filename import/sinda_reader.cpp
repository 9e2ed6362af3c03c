// Reading SINDA/FLUINT files: comment lines, HEADER blocks, INSERT, PSTOP/PSTART and END OF DATA;
// each block's lines go to its reader (sinda_lines.hpp), and lines not translated or ignored are
// reported in groups of consecutive lines with the same reason.

#include "import/sinda_deck.hpp"
#include "import/sinda_lines.hpp"
#include "lang/display_text.hpp"

#include <fmt/format.h>

namespace thermnet::importer::sinda {

namespace {

enum class Block {
  none,         // before the first HEADER
  skip,         // a HEADER that was wrong (reported): its lines are not read
  node,         // NODE DATA
  conductor,    // CONDUCTOR DATA
  source,       // SOURCE DATA
  control,      // CONTROL DATA
  options,      // OPTIONS DATA
  variables0,   // VARIABLES 0
  operations,   // OPERATIONS
  output_calls, // OUTPUT CALLS
  other         // any other block: not translated
};

/// Whether a line starts with `word` (any case) followed by a blank or its end, after `skip`
/// leading characters.
bool starts_with_word(std::string_view text, std::string_view word) {
  if (text.size() < word.size() || upper(text.substr(0, word.size())) != word) return false;
  return text.size() == word.size() || blank(text[word.size()]);
}

/// A group of consecutive lines of one file ignored or not translated for one reason.
struct Run {
  bool open = false;
  LineUse use = LineUse::used;
  std::string why;
  std::string block;
  lang::Span first;
  std::uint32_t first_line = 0;
  std::uint32_t last_line = 0;
};

class DeckReader {
public:
  DeckReader(lang::SourceManager& sources, Report& report) : sources_(sources), report_(report) {}

  void read_root(const std::string& path) {
    lang::FileId id = 0;
    try {
      id = read_input(path, sources_);
    } catch (const InputFileError& e) {
      report_.file_error(path, e.unreadable ? "file-unreadable" : "invalid-encoding", e.what());
      return;
    }
    if (!includes_.push_root(path, report_)) return;
    block_ = Block::none;
    read_file(id);
    flush();
  }

  Deck take() {
    flush();
    deck_.files = includes_.files_read();
    return std::move(deck_);
  }

private:
  void read_file(lang::FileId id) {
    for (const SourceLine& line : lines_of(sources_, id)) {
      if (report_.saturated()) return;
      const std::string_view text = line.text;
      if (is_comment_line(text) || trim(strip_comment(text)).empty()) continue;
      const std::string_view body = trim(text);
      if (starts_with_word(text, "END") && upper(trim(strip_comment(text))) == "END OF DATA") {
        flush();
        return;
      }
      if (starts_with_word(body, "HEADER")) {
        flush();
        if (!starts_with_word(text, "HEADER")) {
          report_.error(line.whole(), "bad-syntax", "HEADER must start in column 1");
          block_ = Block::skip;
          continue;
        }
        if (header(line)) return; // HEADER END OF DATA
        continue;
      }
      if (starts_with_word(body, "PSTOP") || starts_with_word(body, "PSTART")) continue;
      if (starts_with_word(body, "INSERT")) {
        insert(line, trim(strip_comment(body).substr(6)));
        continue;
      }
      try {
        use(line, dispatch(line));
      } catch (const ImportError& e) {
        flush();
        report_.error(e);
      }
    }
  }

  void insert(const SourceLine& line, std::string_view name) {
    flush();
    std::string file(name);
    if (file.size() >= 2 && (file.front() == '\'' || file.front() == '"') &&
        file.back() == file.front())
      file = file.substr(1, file.size() - 2);
    const lang::Span at = line.whole();
    if (auto id = includes_.enter(file, at, sources_, report_)) {
      read_file(*id);
      flush();
      includes_.pop();
    }
  }

  /// Reads a HEADER line; returns true for HEADER END OF DATA.
  bool header(const SourceLine& line) {
    const std::string_view rest = strip_comment(line.text).substr(6);
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (;;) {
      const std::size_t comma = rest.find(',', start);
      std::string part = upper(trim(rest.substr(start, comma - start)));
      // Collapse inner runs of blanks ("NODE   DATA").
      std::string collapsed;
      for (const char c : part)
        if (!blank(c) || (!collapsed.empty() && collapsed.back() != ' '))
          collapsed += blank(c) ? ' ' : c;
      parts.push_back(collapsed);
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    const std::string& name = parts[0];
    sub_ = parts.size() > 1 ? parts[1] : "";
    block_at_ = line.whole();
    if (!deck_.first_header) deck_.first_header = line.whole();
    block_label_ = sub_.empty() ? name : name + ", " + sub_;
    if (name == "END OF DATA") return true;
    if (name.empty()) {
      report_.error(line.whole(), "bad-syntax",
                    "HEADER needs a block name, e.g. HEADER NODE DATA, MAIN");
      block_ = Block::skip;
      return false;
    }
    struct Known {
      const char* name;
      Block block;
      bool needs_sub;
    };
    static constexpr Known known[] = {{"NODE DATA", Block::node, true},
                                      {"CONDUCTOR DATA", Block::conductor, true},
                                      {"SOURCE DATA", Block::source, true},
                                      {"CONTROL DATA", Block::control, false},
                                      {"OPTIONS DATA", Block::options, false},
                                      {"VARIABLES 0", Block::variables0, true},
                                      {"OPERATIONS", Block::operations, false},
                                      {"OPERATIONS DATA", Block::operations, false},
                                      {"OUTPUT CALLS", Block::output_calls, false}};
    block_ = Block::other;
    for (const Known& k : known) {
      if (name != k.name) continue;
      block_ = k.block;
      if (k.block == Block::control && !deck_.control.at) deck_.control.at = line.whole();
      if (k.needs_sub && sub_.empty()) {
        report_.error(line.whole(), "bad-syntax",
                      fmt::format("HEADER {} needs a submodel name: HEADER {}, NAME", name, name));
        block_ = Block::skip;
      } else if (k.needs_sub && !is_identifier(sub_)) {
        report_.error(line.whole(), "bad-syntax",
                      fmt::format("submodel name '{}' is not a name thermnet can keep (letters, "
                                  "digits and _, not starting with a digit)",
                                  lang::excerpt_for_display(sub_)));
        block_ = Block::skip;
      }
    }
    return false;
  }

  LineResult dispatch(const SourceLine& line) {
    switch (block_) {
    case Block::none:
      throw ImportError(line.whole(), "bad-syntax",
                        "data before the first HEADER line (a block starts with HEADER NODE DATA, "
                        "SUBMODEL in column 1)");
    case Block::skip:
      return {};
    case Block::node:
      return node_line(line, sub_, deck_);
    case Block::conductor:
      return conductor_line(line, sub_, deck_);
    case Block::source:
      return source_line(line, sub_, deck_);
    case Block::control:
      return control_line(line, deck_);
    case Block::options:
      return options_line(line, deck_);
    case Block::variables0:
      return variables0_line(line, sub_, deck_);
    case Block::operations:
      return operations_line(line, deck_);
    case Block::output_calls:
      return output_calls_line(line);
    case Block::other:
      return {LineUse::dropped, "the block"};
    }
    return {};
  }

  void use(const SourceLine& line, const LineResult& r) {
    if (r.use == LineUse::used) {
      flush();
      return;
    }
    const std::string why =
        block_ == Block::other ? "the whole block (thermnet does not read it)" : r.why;
    if (run_.open && (run_.use != r.use || run_.why != why || run_.first.file != line.file))
      flush();
    if (!run_.open)
      run_ = Run{true, r.use, why, block_label_, line.whole(), line.number, line.number};
    run_.last_line = line.number;
  }

  void flush() {
    if (!run_.open) return;
    run_.open = false;
    const std::string where = run_.first_line == run_.last_line
                                  ? fmt::format("line {}", run_.first_line)
                                  : fmt::format("lines {}-{}", run_.first_line, run_.last_line);
    const std::string text = fmt::format("HEADER {}, {}: {}", run_.block, where, run_.why);
    if (run_.use == LineUse::dropped)
      report_.dropped(run_.first, text);
    else
      report_.note(run_.first, "ignored: " + text);
  }

  lang::SourceManager& sources_;
  Report& report_;
  Deck deck_;
  IncludeStack includes_;
  Block block_ = Block::none;
  std::string sub_;
  std::string block_label_;
  lang::Span block_at_;
  Run run_;
};

} // namespace

Deck read_deck(const std::vector<std::string>& paths, lang::SourceManager& sources,
               Report& report) {
  DeckReader reader(sources, report);
  for (const auto& path : paths)
    reader.read_root(path);
  return reader.take();
}

} // namespace thermnet::importer::sinda
