// The events file of `thermnet diagnose --events`: parsing with row/column errors, and the
// schedule (1 while on) of one event in one case.

#include "kernel/diagnosis/events.hpp"

#include "lang/csv.hpp"
#include "lang/display_text.hpp"
#include "lang/on_off_words.hpp"
#include "lang/source.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <string_view>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

namespace thermnet {
namespace {

bool is_name(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  return std::all_of(s.begin(), s.end(),
                     [](unsigned char c) { return std::isalnum(c) || c == '_'; });
}

/// Column positions of the header (-1: absent).
struct Columns {
  int start = -1, end = -1, case_name = -1, event = -1, time = -1;
  std::size_t count = 0;
};

Columns header(const std::vector<std::string>& fields, const std::string& path, std::size_t line) {
  Columns c;
  c.count = fields.size();
  for (std::size_t i = 0; i < fields.size(); ++i) {
    int* slot = fields[i] == "start"   ? &c.start
                : fields[i] == "end"   ? &c.end
                : fields[i] == "case"  ? &c.case_name
                : fields[i] == "event" ? &c.event
                : fields[i] == "time"  ? &c.time
                                       : nullptr;
    if (!slot)
      throw lang::CsvError(path, line, i + 1,
                           fmt::format("unknown column '{}' (the columns are case, event, start "
                                       "and end; or time, event and case for a log)",
                                       lang::excerpt_for_display(fields[i])));
    if (*slot >= 0)
      throw lang::CsvError(path, line, i + 1, fmt::format("column '{}' appears twice", fields[i]));
    *slot = static_cast<int>(i);
  }
  if (c.time >= 0 && (c.start >= 0 || c.end >= 0))
    throw lang::CsvError(path, line, static_cast<std::size_t>(c.time) + 1,
                         "a file lists windows (start, end) or a log (time, event), not both");
  if (c.time >= 0 && c.event < 0)
    throw lang::CsvError(path, line, 0,
                         "a log names the columns 'time' and 'event' (\"Lid Opened\", \"Lid "
                         "Closed\"), and may name 'case'");
  if (c.time < 0 && (c.start < 0 || c.end < 0))
    throw lang::CsvError(path, line, 0,
                         "the header must name the columns 'start' and 'end' (times in s), and "
                         "may name 'case' and 'event'; or, for a log, 'time' and 'event'");
  return c;
}

double time_field(const std::vector<std::string>& fields, int col, const std::string& path,
                  std::size_t line) {
  const std::string& f = fields[static_cast<std::size_t>(col)];
  double v = 0.0;
  if (!lang::csv_number(f, v) || !std::isfinite(v))
    throw lang::CsvError(path, line, static_cast<std::size_t>(col) + 1,
                         fmt::format("'{}' is not a time in s", lang::excerpt_for_display(f)));
  return v;
}

/// True when windows `a` and `b` belong to one event in one case (an every-case window is in each)
/// and share some time.
bool clash(const EventWindow& a, const EventWindow& b) {
  const bool same_case = a.case_name.empty() || b.case_name.empty() || a.case_name == b.case_name;
  return a.event == b.event && same_case && a.start < b.end && b.start < a.end;
}

/// True when two of the first `m` windows clash; `by_start` orders every window by event, then
/// start. One pass: a window clashes with one that starts no later exactly when that one ends
/// after it starts.
bool clash_among(const std::vector<EventWindow>& w, const std::vector<std::size_t>& by_start,
                 std::size_t m) {
  constexpr double never = -std::numeric_limits<double>::infinity();
  const std::string* event = nullptr;
  double every_case_end = never, any_end = never; // latest end so far, of this event
  std::unordered_map<std::string_view, double> case_end;
  for (const std::size_t i : by_start) {
    if (i >= m) continue;
    const EventWindow& x = w[i];
    if (!event || x.event != *event) {
      event = &x.event;
      every_case_end = any_end = never;
      case_end.clear();
    }
    if (x.case_name.empty()) {
      if (x.start < any_end) return true;
      every_case_end = std::max(every_case_end, x.end);
    } else {
      double& own = case_end.try_emplace(x.case_name, never).first->second;
      if (x.start < std::max(every_case_end, own)) return true;
      own = std::max(own, x.end);
    }
    any_end = std::max(any_end, x.end);
  }
  return false;
}

/// The first window (in file order) that clashes with an earlier one, and the first such earlier
/// one; {0, 0} when none clash. O(n log n): the shortest clashing prefix is found by bisection.
std::pair<std::size_t, std::size_t> first_overlap(const std::vector<EventWindow>& w) {
  std::vector<std::size_t> by_start(w.size());
  std::iota(by_start.begin(), by_start.end(), std::size_t{0});
  std::sort(by_start.begin(), by_start.end(), [&](std::size_t a, std::size_t b) {
    return std::tie(w[a].event, w[a].start) < std::tie(w[b].event, w[b].start);
  });
  if (!clash_among(w, by_start, w.size())) return {0, 0};
  std::size_t lo = 1, hi = w.size(); // the first lo windows do not clash, the first hi do
  while (hi - lo > 1) {
    const std::size_t mid = lo + (hi - lo) / 2;
    (clash_among(w, by_start, mid) ? hi : lo) = mid;
  }
  const std::size_t later = hi - 1;
  for (std::size_t i = 0; i < later; ++i)
    if (clash(w[i], w[later])) return {later, i};
  return {0, 0}; // not reached: window `later` clashes with an earlier one
}

/// The case a row names (empty: every case); an unknown case is an error at its cell.
std::string case_field(const std::vector<std::string>& fields, const Columns& cols,
                       const std::string& path, std::size_t line,
                       const std::vector<std::string>& cases) {
  if (cols.case_name < 0) return "";
  const std::string& c = fields[static_cast<std::size_t>(cols.case_name)];
  if (c == "*" || c.empty()) return "";
  if (!cases.empty() && std::find(cases.begin(), cases.end(), c) == cases.end())
    throw lang::CsvError(path, line, static_cast<std::size_t>(cols.case_name) + 1,
                         fmt::format("the model has no case '{}' (its cases: {})",
                                     lang::excerpt_for_display(c), fmt::join(cases, ", ")));
  return c;
}

/// One row of an event log.
struct LogRow {
  double time = 0.0;     // as written
  std::string event;     // the event's name
  bool on = false;       // its on/off word
  std::string case_name; // empty: every case
  std::size_t line = 0;
};

/// The name of a log's event text before its on/off word ("Lid Opened" -> lid, "Door 2 open" ->
/// door_2; "on" alone -> event).
std::string log_event_name(const std::string& text) {
  const std::size_t space = text.find_last_of(" \t");
  std::string name;
  if (space != std::string::npos)
    for (char ch : text.substr(0, space)) {
      const auto c = static_cast<unsigned char>(ch);
      if (std::isalnum(c))
        name += static_cast<char>(std::tolower(c));
      else if (!name.empty() && name.back() != '_')
        name += '_';
    }
  while (!name.empty() && name.back() == '_')
    name.pop_back();
  if (name.empty()) return "event";
  return std::isdigit(static_cast<unsigned char>(name[0])) ? "event_" + name : name;
}

/// A row of a log: its time, and the event's name and on/off word ("Lid Opened").
LogRow log_row(const std::vector<std::string>& fields, const Columns& cols, const std::string& path,
               std::size_t line, const std::vector<std::string>& cases) {
  LogRow r;
  r.line = line;
  r.time = time_field(fields, cols.time, path, line);
  const std::string& text = fields[static_cast<std::size_t>(cols.event)];
  const auto word = lang::on_off_word(text);
  if (!word)
    throw lang::CsvError(path, line, static_cast<std::size_t>(cols.event) + 1,
                         fmt::format("'{}' does not end in an on/off word (opened/closed, on/off, "
                                     "start/stop, true/false)",
                                     lang::excerpt_for_display(text)));
  r.on = *word > 0.5;
  r.event = log_event_name(text);
  r.case_name = case_field(fields, cols, path, line, cases);
  return r;
}

/// The windows of a log's rows: from each on to the next off of the same event and case.
std::vector<EventWindow> log_windows(std::vector<LogRow> rows, const std::string& path,
                                     const Columns& cols, std::vector<std::size_t>& lines) {
  // UNIX times (s, ms, us or ns by magnitude) or seconds from the start of each case.
  constexpr double unix_from = 1e8;
  double largest = 0.0;
  for (const auto& r : rows)
    largest = std::max(largest, r.time);
  const bool absolute = largest >= unix_from;
  const double scale = largest >= 1e17   ? 1e-9
                       : largest >= 1e14 ? 1e-6
                       : largest >= 1e11 ? 1e-3
                                         : 1.0;
  for (const auto& r : rows)
    if (absolute ? r.time * scale < unix_from : r.time < 0.0)
      throw lang::CsvError(
          path, r.line, static_cast<std::size_t>(cols.time) + 1,
          absolute ? fmt::format("time {:g} is not a UNIX time like the log's others (times of 1e8 "
                                 "or more are UNIX times; smaller ones are s from the start of "
                                 "the case)",
                                 r.time)
                   : fmt::format("time {:g} is negative; cases start at 0 s", r.time));
  std::stable_sort(rows.begin(), rows.end(), [](const LogRow& a, const LogRow& b) {
    return std::tie(a.case_name, a.event, a.time) < std::tie(b.case_name, b.event, b.time);
  });
  constexpr double inf = std::numeric_limits<double>::infinity();
  const double case_start = absolute ? -inf : 0.0;
  std::vector<EventWindow> out;
  auto close = [&](const LogRow& from, double start, double end, std::size_t line) {
    if (!(end > start)) return; // opened and closed at one time: never on
    out.push_back(EventWindow{from.case_name, from.event, start, end, absolute});
    lines.push_back(line);
  };
  std::optional<std::size_t> open; // the row that turned the current event on
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const LogRow& r = rows[i];
    if (i > 0 && (r.case_name != rows[i - 1].case_name || r.event != rows[i - 1].event)) {
      if (open) close(rows[*open], rows[*open].time * scale, inf, rows[*open].line);
      open.reset();
    }
    if (r.on) {
      if (!open) open = i;
    } else if (open) {
      close(r, rows[*open].time * scale, r.time * scale, rows[*open].line);
      open.reset();
    } else if (i == 0 || r.case_name != rows[i - 1].case_name || r.event != rows[i - 1].event) {
      close(r, case_start, r.time * scale, r.line); // on from the start of the case
    }
  }
  if (open) close(rows[*open], rows[*open].time * scale, inf, rows[*open].line);
  return out;
}

} // namespace

std::vector<EventWindow> parse_events(const std::string& text, const std::string& path,
                                      const std::vector<std::string>& cases) {
  std::vector<EventWindow> out;
  std::vector<std::size_t> lines;
  std::vector<LogRow> log;
  Columns cols;
  bool have_header = false;
  std::size_t line_no = 0;
  // A byte order mark before the header is skipped, as in data files.
  std::size_t pos = std::string_view(text).starts_with("\xEF\xBB\xBF") ? 3 : 0;
  while (pos <= text.size()) {
    const auto nl = text.find('\n', pos);
    const std::string_view line(text.data() + pos,
                                (nl == std::string::npos ? text.size() : nl) - pos);
    pos = nl == std::string::npos ? text.size() + 1 : nl + 1;
    ++line_no;
    const auto fields = lang::csv_fields(line);
    if (fields.size() == 1 && fields[0].empty()) continue;
    if (line.find('\0') != std::string_view::npos)
      throw lang::CsvError(path, line_no, 0, "contains a NUL byte; is this a binary file?");
    if (!have_header) {
      cols = header(fields, path, line_no);
      have_header = true;
      continue;
    }
    if (fields.size() != cols.count)
      throw lang::CsvError(
          path, line_no, 0,
          fmt::format("row has {} fields, the header has {}", fields.size(), cols.count));
    if (cols.time >= 0) {
      log.push_back(log_row(fields, cols, path, line_no, cases));
      continue;
    }
    EventWindow w;
    w.start = time_field(fields, cols.start, path, line_no);
    w.end = time_field(fields, cols.end, path, line_no);
    if (w.start < 0.0)
      throw lang::CsvError(path, line_no, static_cast<std::size_t>(cols.start) + 1,
                           fmt::format("start {:g} is negative; cases start at 0 s", w.start));
    if (!(w.end > w.start))
      throw lang::CsvError(path, line_no, static_cast<std::size_t>(cols.end) + 1,
                           fmt::format("end {:g} is not after start {:g}", w.end, w.start));
    w.case_name = case_field(fields, cols, path, line_no, cases);
    w.event = "event";
    if (cols.event >= 0 && !fields[static_cast<std::size_t>(cols.event)].empty()) {
      w.event = fields[static_cast<std::size_t>(cols.event)];
      if (!is_name(w.event))
        throw lang::CsvError(path, line_no, static_cast<std::size_t>(cols.event) + 1,
                             fmt::format("event name '{}' must be a name (letters, digits, _)",
                                         lang::excerpt_for_display(w.event)));
    }
    out.push_back(std::move(w));
    lines.push_back(line_no);
  }
  if (!have_header)
    throw lang::CsvError(path, 1, 0,
                         "the file is empty; expected a header row 'case,event,start,end'");
  if (cols.time >= 0) out = log_windows(std::move(log), path, cols, lines);
  if (out.empty()) throw lang::CsvError(path, line_no, 0, "the file lists no event");
  if (const auto [later, earlier] = first_overlap(out); later > 0) {
    const EventWindow& w = out[later];
    throw lang::CsvError(path, lines[later], static_cast<std::size_t>(cols.start) + 1,
                         fmt::format("{} from {:g} to {:g} s overlaps its window of row {}",
                                     w.event, w.start, w.end, lines[earlier]));
  }
  return out;
}

std::vector<EventWindow> read_events(const std::string& path,
                                     const std::vector<std::string>& cases) {
  std::string text;
  if (auto error = lang::read_text_file(path, text)) throw lang::CsvError(path, 0, 0, *error);
  return parse_events(text, path, cases);
}

std::vector<EventWindow> place_events(const std::vector<EventWindow>& events,
                                      const std::vector<CaseClock>& cases,
                                      const std::string& path) {
  std::vector<EventWindow> out;
  bool any_absolute = false, placed_absolute = false;
  for (const auto& w : events) {
    any_absolute = any_absolute || w.absolute;
    if (!w.absolute && std::isfinite(w.start) && std::isfinite(w.end)) {
      out.push_back(w);
      continue;
    }
    for (const auto& c : cases) {
      if (!w.case_name.empty() && w.case_name != c.name) continue;
      if (w.absolute && !c.epoch) continue;
      const double shift = w.absolute ? *c.epoch : 0.0;
      const double start = std::max(0.0, w.start - shift),
                   end = std::min(c.duration, w.end - shift);
      if (!(end > start)) continue;
      out.push_back(EventWindow{c.name, w.event, start, end, false});
      placed_absolute = placed_absolute || w.absolute;
    }
  }
  if (any_absolute && !placed_absolute)
    throw lang::CsvError(path, 0, 0,
                         "the log's UNIX times fall in no case (a case is placed in time by its "
                         "data file's UNIX or ISO times)");
  return out;
}

std::vector<std::string> event_names(const std::vector<EventWindow>& events) {
  std::vector<std::string> names;
  std::unordered_set<std::string_view> seen;
  for (const auto& w : events)
    if (seen.insert(w.event).second) names.push_back(w.event);
  return names;
}

lang::Signal event_schedule(const std::vector<EventWindow>& events, const std::string& case_name,
                            const std::string& event) {
  std::vector<const EventWindow*> on;
  for (const auto& w : events)
    if (w.event == event && (w.case_name.empty() || w.case_name == case_name)) on.push_back(&w);
  if (on.empty()) return lang::Signal::of(0.0);
  std::sort(on.begin(), on.end(), [](auto* a, auto* b) { return a->start < b->start; });
  lang::Signal s;
  lang::Signal::Shape& corners = s.shape(lang::Signal::Kind::step);
  auto point = [&](double t, double v) {
    if (!corners.t.empty() && corners.t.back() == t) { // a window starting where the last one ended
      corners.t.pop_back();
      corners.v.pop_back();
      if (!corners.v.empty() && corners.v.back() == v) return;
    }
    corners.t.push_back(t);
    corners.v.push_back(v);
  };
  if (on.front()->start > 0.0) point(0.0, 0.0);
  for (const auto* w : on) {
    point(w->start, 1.0);
    point(w->end, 0.0);
  }
  return s;
}

} // namespace thermnet
