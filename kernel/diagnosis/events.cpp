// The events file of `thermnet diagnose --events`: parsing with row/column errors, and the
// schedule (1 while on) of one event in one case.

#include "kernel/diagnosis/events.hpp"

#include "lang/csv.hpp"
#include "lang/display_text.hpp"
#include "lang/source.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <numeric>
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
  int start = -1, end = -1, case_name = -1, event = -1;
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
                                       : nullptr;
    if (!slot)
      throw lang::CsvError(path, line, i + 1,
                           fmt::format("unknown column '{}' (the columns are case, event, start "
                                       "and end)",
                                       lang::excerpt_for_display(fields[i])));
    if (*slot >= 0)
      throw lang::CsvError(path, line, i + 1, fmt::format("column '{}' appears twice", fields[i]));
    *slot = static_cast<int>(i);
  }
  if (c.start < 0 || c.end < 0)
    throw lang::CsvError(path, line, 0,
                         "the header must name the columns 'start' and 'end' (times in s), and "
                         "may name 'case' and 'event'");
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

} // namespace

std::vector<EventWindow> parse_events(const std::string& text, const std::string& path,
                                      const std::vector<std::string>& cases) {
  std::vector<EventWindow> out;
  std::vector<std::size_t> lines;
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
    EventWindow w;
    w.start = time_field(fields, cols.start, path, line_no);
    w.end = time_field(fields, cols.end, path, line_no);
    if (w.start < 0.0)
      throw lang::CsvError(path, line_no, static_cast<std::size_t>(cols.start) + 1,
                           fmt::format("start {:g} is negative; cases start at 0 s", w.start));
    if (!(w.end > w.start))
      throw lang::CsvError(path, line_no, static_cast<std::size_t>(cols.end) + 1,
                           fmt::format("end {:g} is not after start {:g}", w.end, w.start));
    if (cols.case_name >= 0) {
      const std::string& c = fields[static_cast<std::size_t>(cols.case_name)];
      if (c != "*" && !c.empty()) {
        if (!cases.empty() && std::find(cases.begin(), cases.end(), c) == cases.end())
          throw lang::CsvError(path, line_no, static_cast<std::size_t>(cols.case_name) + 1,
                               fmt::format("the model has no case '{}' (its cases: {})",
                                           lang::excerpt_for_display(c), fmt::join(cases, ", ")));
        w.case_name = c;
      }
    }
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
