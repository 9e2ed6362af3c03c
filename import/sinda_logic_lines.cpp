// CONTROL DATA, OPTIONS DATA, VARIABLES 0, OPERATIONS and OUTPUT CALLS lines of a SINDA/FLUINT
// deck: the few forms thermnet translates, the output and solver settings that change no
// temperature, and user logic (not translated).

#include "import/fortran_number.hpp"
#include "import/sinda_lines.hpp"
#include "lang/display_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace thermnet::importer::sinda {

namespace {

/// The line in upper case without blanks or its `$` comment.
std::string squeezed(std::string_view text) {
  std::string out;
  for (const char c : strip_comment(text))
    if (!blank(c)) out += c;
  return upper(out);
}

/// A Fortran line (F or M in column 1) or any statement: user logic.
LineResult logic() {
  return {LineUse::dropped, "user logic"};
}

void set_once(std::optional<ControlValue>& slot, double value, lang::Span at, const char* name) {
  if (slot && slot->value != value)
    throw ImportError(
        at, "duplicate-name",
        fmt::format("{} is set twice, to {} and before to {}", name, value, slot->value));
  slot = ControlValue{value, at};
}

} // namespace

LineResult control_line(const SourceLine& line, Deck& deck) {
  const std::string_view text = strip_comment(line.text);
  std::vector<std::string> ignored;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t comma = text.find(',', start);
    if (comma == std::string_view::npos) comma = text.size();
    const std::string_view part = text.substr(start, comma - start);
    const std::size_t first = part.find_first_not_of(" \t");
    const std::size_t lead = first == std::string_view::npos ? part.size() : first;
    const lang::Span at = line.span(start + lead, comma);
    const std::string_view item = trim(part);
    start = comma + 1;
    if (item.empty()) continue;
    const std::size_t eq = item.find('=');
    if (eq == std::string_view::npos) {
      ignored.push_back(upper(item));
      continue;
    }
    const std::string name = upper(trim(item.substr(0, eq)));
    std::string_view value = trim(item.substr(eq + 1));
    if (name == "UID") {
      std::string v = upper(value);
      v.erase(std::remove(v.begin(), v.end(), '\''), v.end());
      v.erase(std::remove(v.begin(), v.end(), '"'), v.end());
      if (v != "SI" && v != "ENG")
        throw ImportError(
            at, "invalid-value",
            fmt::format("UID must be SI or ENG, not '{}'", lang::excerpt_for_display(value)));
      if (deck.control.uid && *deck.control.uid != v)
        throw ImportError(
            at, "duplicate-name",
            fmt::format("UID is set twice, to {} and before to {}", v, *deck.control.uid));
      deck.control.uid = v;
      deck.control.uid_at = at;
      continue;
    }
    static constexpr std::array<const char*, 5> used = {"ABSZRO", "SIGMA", "TIMEND", "TIMEO",
                                                        "OUTPUT"};
    if (std::find(used.begin(), used.end(), name) == used.end()) {
      ignored.push_back(name);
      continue;
    }
    const RealResult r = parse_fortran_real(value);
    if (r.problem != NumberProblem::none)
      throw ImportError(at, "bad-number", fortran_number_message(value, r.problem));
    if (name == "ABSZRO") set_once(deck.control.abszro, r.value, at, "ABSZRO");
    if (name == "SIGMA") set_once(deck.control.sigma, r.value, at, "SIGMA");
    if (name == "TIMEND") set_once(deck.control.timend, r.value, at, "TIMEND");
    if (name == "TIMEO") set_once(deck.control.timeo, r.value, at, "TIMEO");
    if (name == "OUTPUT") set_once(deck.control.output, r.value, at, "OUTPUT");
  }
  if (ignored.empty()) return {};
  return {LineUse::ignored, "solver and output settings, not needed by thermnet (it chooses its "
                            "own time steps and tolerances)"};
}

LineResult options_line(const SourceLine& line, Deck& deck) {
  const std::string_view text = trim(strip_comment(line.text));
  if (upper(text.substr(0, 5)) == "TITLE" && (text.size() == 5 || blank(text[5]))) {
    std::string_view title = trim(text.substr(5));
    if (title.size() >= 2 && (title.front() == '\'' || title.front() == '"') &&
        title.back() == title.front())
      title = title.substr(1, title.size() - 2);
    if (deck.title.empty()) deck.title = std::string(title);
    return {};
  }
  if (text.empty()) return {};
  return {LineUse::ignored, "output files and options, which change no temperature"};
}

LineResult variables0_line(const SourceLine& line, const std::string& sub, Deck& deck) {
  if (!line.text.empty() &&
      (line.text[0] == 'F' || line.text[0] == 'f' || line.text[0] == 'M' || line.text[0] == 'm'))
    return logic();
  const std::string s = squeezed(line.text);
  if (s.empty()) return {};
  const std::size_t eq = s.find('=');
  if (eq == std::string::npos) return logic();
  // `LHS = LHS + value`, `LHS = LHS - value` or `LHS = value + LHS`, LHS being `SUB.Qn` or `Qn`.
  const std::string lhs = s.substr(0, eq);
  const std::string rhs = s.substr(eq + 1);
  const auto node_of = [&](const std::string& q) -> std::optional<NodeRef> {
    const std::size_t dot = q.find('.');
    std::string owner = dot == std::string::npos ? sub : q.substr(0, dot);
    std::string rest = dot == std::string::npos ? q : q.substr(dot + 1);
    if (rest.size() < 2 || rest[0] != 'Q' || !is_identifier(owner)) return std::nullopt;
    auto id = parse_fortran_integer(rest.substr(1));
    if (!id || *id <= 0 || rest[1] == '+') return std::nullopt;
    return NodeRef{owner, *id, line.whole()};
  };
  const auto target = node_of(lhs);
  if (!target) return logic();
  std::string number;
  if (rhs.size() > lhs.size() && rhs.compare(0, lhs.size(), lhs) == 0 &&
      (rhs[lhs.size()] == '+' || rhs[lhs.size()] == '-')) {
    number = rhs.substr(lhs.size());
  } else {
    const std::size_t plus = rhs.rfind('+');
    if (plus == std::string::npos || plus == 0) return logic();
    const auto tail = node_of(rhs.substr(plus + 1));
    if (!tail || tail->sub != target->sub || tail->id != target->id) return logic();
    number = rhs.substr(0, plus);
  }
  const RealResult r = parse_fortran_real(number);
  if (r.problem != NumberProblem::none) return logic();
  deck.sources.push_back({*target, r.value, line.whole(), true});
  return {};
}

namespace {

/// The routine a `CALL NAME(...)` line calls, upper case ("" when the line is not a call).
std::string called(const std::string& s) {
  if (s.compare(0, 4, "CALL") != 0) return "";
  const std::size_t paren = s.find('(', 4);
  return s.substr(4, paren == std::string::npos ? std::string::npos : paren - 4);
}

/// Routines that print, plot or save results and change no temperature.
bool output_routine(const std::string& name) {
  static constexpr std::array<const char*, 12> names = {"SAVE",   "RESAVE", "QMAP",   "QMAPS",
                                                        "NODTAB", "TABS",   "CSRMAP", "SAVEPAR",
                                                        "RECORD", "HTRMAP", "REGTAB", "LMPTAB"};
  return name.find("PRINT") != std::string::npos ||
         std::find(names.begin(), names.end(), name) != names.end();
}

} // namespace

LineResult operations_line(const SourceLine& line, Deck& deck) {
  if (!line.text.empty() &&
      (line.text[0] == 'F' || line.text[0] == 'f' || line.text[0] == 'M' || line.text[0] == 'm'))
    return logic();
  const std::string s = squeezed(line.text);
  if (s.empty()) return {};
  if (s.compare(0, 5, "BUILD") == 0) {
    // BUILD ALL, or BUILD CONFIG, SUB1, SUB2 ... (BUILDF builds fluid submodels: none here)
    if (s.compare(0, 6, "BUILDF") == 0) return {};
    std::string words = upper(trim(strip_comment(line.text)).substr(5));
    for (char& c : words)
      if (c == ',') c = ' ';
    std::vector<std::string> names;
    std::size_t i = 0;
    while (i < words.size()) {
      while (i < words.size() && blank(words[i]))
        ++i;
      std::size_t j = i;
      while (j < words.size() && !blank(words[j]))
        ++j;
      if (j > i) names.push_back(words.substr(i, j - i));
      i = j;
    }
    Build build{{}, line.whole()};
    if (!(names.size() == 1 && names[0] == "ALL"))
      build.subs.assign(names.size() > 1 ? names.begin() + 1 : names.begin(), names.end());
    deck.builds.push_back(std::move(build));
    return {};
  }
  const std::string routine = called(s);
  if (routine == "STEADY" || routine == "STDSTL" || routine == "FASTIC") {
    if (!deck.steady) deck.steady = line.whole();
    return {};
  }
  if (routine == "TRANSIENT" || routine == "FWDBCK" || routine == "FORWRD" ||
      routine == "FORWARD" || routine == "EXPLCT") {
    if (!deck.transient) deck.transient = line.whole();
    return {};
  }
  if (!routine.empty() && output_routine(routine))
    return {LineUse::ignored, "output calls, which change no temperature"};
  return logic();
}

LineResult output_calls_line(const SourceLine& line) {
  if (!line.text.empty() &&
      (line.text[0] == 'F' || line.text[0] == 'f' || line.text[0] == 'M' || line.text[0] == 'm'))
    return logic();
  const std::string s = squeezed(line.text);
  if (s.empty()) return {};
  const std::string routine = called(s);
  if (!routine.empty() && output_routine(routine))
    return {LineUse::ignored, "output calls, which change no temperature"};
  return logic();
}

} // namespace thermnet::importer::sinda
