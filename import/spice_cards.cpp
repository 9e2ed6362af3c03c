#include "import/spice_cards.hpp"

#include "lang/display_text.hpp"

#include <fmt/format.h>

#include <cctype>

namespace thermnet::importer::spice {

std::string lower(std::string_view text) {
  std::string out(text);
  for (char& c : out)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

namespace {

bool blank(char c) {
  return c == ' ' || c == '\t' || c == '\v' || c == '\f' || c == ',';
}

/// The tokens of a physical line from character `from` on (up to its `;` comment).
void tokenize(const SourceLine& line, std::size_t from, std::vector<Token>& out) {
  const std::string_view t = line.text;
  std::size_t i = from;
  while (i < t.size()) {
    const char c = t[i];
    if (blank(c)) {
      ++i;
      continue;
    }
    if (c == ';') break;
    Token tok;
    if (c == '(' || c == ')' || c == '=') {
      tok.kind = c == '(' ? Token::Kind::open : c == ')' ? Token::Kind::close : Token::Kind::equals;
      tok.text = std::string(1, c);
      tok.at = line.span(i, i + 1);
      ++i;
    } else if (c == '{' || c == '\'') {
      const char close = c == '{' ? '}' : '\'';
      const std::size_t end = t.find(close, i + 1);
      if (end == std::string_view::npos)
        throw ImportError(line.span(i, t.size()), "bad-syntax",
                          fmt::format("'{}' without its closing '{}'", c, close));
      tok.kind = Token::Kind::expression;
      tok.text = std::string(t.substr(i + 1, end - i - 1));
      tok.at = line.span(i, end + 1);
      tok.text_offset = line.offset + static_cast<std::uint32_t>(i + 1);
      i = end + 1;
    } else {
      std::size_t j = i;
      while (j < t.size() && !blank(t[j]) && t[j] != '(' && t[j] != ')' && t[j] != '=' &&
             t[j] != ';' && t[j] != '{' && t[j] != '\'')
        ++j;
      tok.text = std::string(t.substr(i, j - i));
      tok.at = line.span(i, j);
      tok.text_offset = line.offset + static_cast<std::uint32_t>(i);
      i = j;
    }
    out.push_back(std::move(tok));
  }
}

bool is_comment(std::string_view line) {
  std::size_t i = 0;
  while (i < line.size() && (line[i] == ' ' || line[i] == '\t'))
    ++i;
  return i == line.size() || line[i] == '*' || line[i] == ';';
}

class CardReader {
public:
  CardReader(lang::SourceManager& sources, Report& report) : sources_(sources), report_(report) {}

  void read_root(const std::string& path, bool title) {
    lang::FileId id = 0;
    try {
      id = read_input(path, sources_);
    } catch (const InputFileError& e) {
      report_.file_error(path, e.unreadable ? "file-unreadable" : "invalid-encoding", e.what());
      return;
    }
    if (!includes_.push_root(path, report_)) return;
    read_file(id, title);
  }

  Netlist take() {
    net_.files = includes_.files_read();
    return std::move(net_);
  }

private:
  void read_file(lang::FileId id, bool title) {
    const std::vector<SourceLine> lines = lines_of(sources_, id);
    std::size_t first = 0;
    if (title && !lines.empty()) {
      net_.title = std::string(lines[0].text);
      net_.title_at = lines[0].whole();
      first = 1;
    }
    Card card;
    const auto finish = [&] {
      if (card.tokens.empty()) return false;
      const bool end = handle(card);
      card = Card{};
      return end;
    };
    for (std::size_t k = first; k < lines.size(); ++k) {
      if (report_.saturated()) return;
      const SourceLine& line = lines[k];
      if (is_comment(line.text)) continue;
      std::size_t lead = 0;
      while (lead < line.text.size() && (line.text[lead] == ' ' || line.text[lead] == '\t'))
        ++lead;
      try {
        if (line.text[lead] == '+') {
          if (card.tokens.empty())
            throw ImportError(line.span(lead, lead + 1), "bad-syntax",
                              "a continuation line ('+') with no card before it");
          tokenize(line, lead + 1, card.tokens);
          continue;
        }
        if (finish()) return;
        card.at = line.whole();
        tokenize(line, lead, card.tokens);
      } catch (const ImportError& e) {
        report_.error(e);
        card = Card{};
      }
    }
    finish();
  }

  /// Handles a finished card: an include is read at once; returns true for `.end`.
  bool handle(Card& card) {
    const std::string head = lower(card.tokens[0].text);
    if (head == ".end") return true;
    if (head == ".include" || head == ".inc") {
      if (card.tokens.size() != 2) {
        report_.error(card.at, "bad-syntax", ".include names one file: .include \"FILE\"");
        return false;
      }
      std::string name = card.tokens[1].text;
      if (name.size() >= 2 && name.front() == '"' && name.back() == '"')
        name = name.substr(1, name.size() - 2);
      if (auto id = includes_.enter(name, card.at, sources_, report_)) {
        read_file(*id, false);
        includes_.pop();
      }
      return false;
    }
    net_.cards.push_back(std::move(card));
    return false;
  }

  lang::SourceManager& sources_;
  Report& report_;
  IncludeStack includes_;
  Netlist net_;
};

} // namespace

Netlist read_cards(const std::vector<std::string>& paths, lang::SourceManager& sources,
                   Report& report) {
  CardReader reader(sources, report);
  for (std::size_t i = 0; i < paths.size(); ++i)
    reader.read_root(paths[i], i == 0);
  return reader.take();
}

} // namespace thermnet::importer::spice
