#include "cli/svg_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <unordered_set>

namespace thermnet::plot {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Okabe-Ito, reordered so the first colours are the most distinct on white; the yellow is
// darkened a little so thin lines stay visible.
constexpr std::array<const char*, 8> kPalette = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                                 "#E69F00", "#56B4E9", "#000000", "#C9B500"};

// Dash patterns cycled by auto-coloured solid series once the colours run out (for width 1.5).
constexpr std::array<const char*, 6> kDashCycle = {"",          "6 4",    "0.1 3.5",
                                                   "8 4 0.1 4", "14 4.5", "8 3.5 0.1 3.5 0.1 3.5"};
constexpr const char* kDashed = "6 4";
constexpr const char* kDotted = "0.1 3.5";
constexpr const char* kDashDot = "8 4 0.1 4";

constexpr const char* kFontFamily =
    "Arial, Helvetica, 'Liberation Sans', 'DejaVu Sans', sans-serif";

constexpr double kTickFont = 11;
constexpr double kLabelFont = 12;
constexpr double kPanelTitleFont = 13;
constexpr double kFigureTitleFont = 16;
constexpr double kMarkerRadius = 2.8;

// ---------------------------------------------------------------------------------------------
// UTF-8 and text helpers

// Length of the UTF-8 sequence starting at s[i], or 0 if it is not valid.
std::size_t utf8_length(std::string_view s, std::size_t i) {
  const auto c = static_cast<unsigned char>(s[i]);
  if (c < 0x80) return 1;
  std::size_t len = 0;
  std::uint32_t cp = 0;
  if ((c & 0xE0) == 0xC0) {
    len = 2;
    cp = c & 0x1F;
  } else if ((c & 0xF0) == 0xE0) {
    len = 3;
    cp = c & 0x0F;
  } else if ((c & 0xF8) == 0xF0) {
    len = 4;
    cp = c & 0x07;
  } else {
    return 0;
  }
  if (i + len > s.size()) return 0;
  for (std::size_t k = 1; k < len; ++k) {
    const auto d = static_cast<unsigned char>(s[i + k]);
    if ((d & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (d & 0x3F);
  }
  // Reject overlong forms, surrogates, out-of-range values and the XML non-characters.
  if ((len == 2 && cp < 0x80) || (len == 3 && cp < 0x800) || (len == 4 && cp < 0x10000)) return 0;
  if ((cp >= 0xD800 && cp <= 0xDFFF) || cp > 0x10FFFF || cp == 0xFFFE || cp == 0xFFFF) return 0;
  return len;
}

// Valid UTF-8 with control characters replaced by spaces and invalid bytes by U+FFFD.
std::string sanitize(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t len = utf8_length(s, i);
    if (len == 0) {
      out += "\xEF\xBF\xBD";
      ++i;
    } else if (len == 1) {
      const auto c = static_cast<unsigned char>(s[i]);
      out += (c < 0x20 || c == 0x7F) ? ' ' : s[i];
      ++i;
    } else {
      out.append(s.substr(i, len));
      i += len;
    }
  }
  return out;
}

// Advance widths (em) of printable ASCII in DejaVu Sans, the widest of the usual sans-serif
// fonts, so layout estimates err on the generous side.
constexpr std::array<double, 95> kAsciiWidth = {
    0.318, 0.400, 0.460, 0.838, 0.636, 0.950, 0.780, 0.275, 0.390, 0.390, 0.500, 0.838,
    0.318, 0.361, 0.318, 0.337, 0.636, 0.636, 0.636, 0.636, 0.636, 0.636, 0.636, 0.636,
    0.636, 0.636, 0.337, 0.337, 0.838, 0.838, 0.838, 0.531, 1.000, 0.684, 0.686, 0.698,
    0.770, 0.632, 0.575, 0.775, 0.752, 0.295, 0.295, 0.656, 0.557, 0.863, 0.748, 0.787,
    0.603, 0.787, 0.695, 0.635, 0.611, 0.732, 0.684, 0.989, 0.685, 0.611, 0.685, 0.390,
    0.337, 0.390, 0.838, 0.500, 0.500, 0.613, 0.635, 0.550, 0.635, 0.615, 0.352, 0.635,
    0.634, 0.278, 0.278, 0.579, 0.278, 0.974, 0.634, 0.612, 0.635, 0.635, 0.411, 0.521,
    0.392, 0.634, 0.592, 0.818, 0.592, 0.592, 0.525, 0.636, 0.337, 0.636, 0.838};

// Estimated advance (em) of the code point starting at s[i] of valid UTF-8; sets len.
double char_em(std::string_view s, std::size_t i, std::size_t& len) {
  const auto c = static_cast<unsigned char>(s[i]);
  if (c < 0x80) {
    len = 1;
    return c >= 0x20 && c < 0x7F ? kAsciiWidth[c - 0x20] : 0.6;
  }
  len = (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : 4;
  if (s.substr(i, len) == "\xE2\x80\xA6") return 1.0; // ellipsis
  return len >= 3 ? 0.9 : 0.7;                        // accented/Greek letters; symbols, CJK
}

// Estimated rendered width of (sanitised) text in px.
double text_width(std::string_view s, double font_size) {
  double em = 0;
  for (std::size_t i = 0, len = 1; i < s.size(); i += len)
    em += char_em(s, i, len);
  return em * font_size;
}

// Valid UTF-8 cut to fit in `width` px at font_size, ending in an ellipsis when cut.
std::string truncate(std::string_view s, double width, double font_size) {
  if (text_width(s, font_size) <= width) return std::string(s);
  const double room = width - 1.0 * font_size; // keep space for the ellipsis
  double used = 0;
  std::size_t i = 0;
  for (std::size_t len = 1; i < s.size(); i += len) {
    const double w = char_em(s, i, len) * font_size;
    if (used + w > room) break;
    used += w;
  }
  std::string out(s.substr(0, i));
  while (!out.empty() && out.back() == ' ')
    out.pop_back();
  return out + "\xE2\x80\xA6";
}

// Sanitised text cut to fit in width px at font_size (bold text is about 10 % wider).
std::string fit_text(std::string_view raw, double width, double font_size, bool bold = false) {
  return truncate(sanitize(raw), bold ? width / 1.1 : width, font_size);
}

// Escapes already sanitised text.
void append_escaped(std::string& out, std::string_view s) {
  for (const char c : s) {
    switch (c) {
    case '&':
      out += "&amp;";
      break;
    case '<':
      out += "&lt;";
      break;
    case '>':
      out += "&gt;";
      break;
    case '"':
      out += "&quot;";
      break;
    case '\'':
      out += "&apos;";
      break;
    default:
      out += c;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Numbers

// Removes trailing zeros of the fraction (and a bare '.'); "-0" becomes "0".
std::string trim_fraction(std::string s) {
  const std::size_t e = s.find_first_of("eE");
  std::string mant = s.substr(0, e);
  const std::string exp = e == std::string::npos ? std::string() : s.substr(e);
  if (mant.find('.') != std::string::npos) {
    while (!mant.empty() && mant.back() == '0')
      mant.pop_back();
    if (!mant.empty() && mant.back() == '.') mant.pop_back();
  }
  if (mant == "-0") mant = "0";
  return mant + exp;
}

// "1.5e6" style: mantissa with `decimals` decimals (trimmed), exponent without sign or zeros.
std::string exponent_form(double v, int decimals) {
  const std::string s = fmt::format("{:.{}e}", v, std::clamp(decimals, 0, 16));
  const std::size_t e = s.find('e');
  const std::string mant = trim_fraction(s.substr(0, e));
  const int exp = std::stoi(s.substr(e + 1));
  if (mant == "0") return "0";
  return exp == 0 ? mant : fmt::format("{}e{}", mant, exp);
}

std::string fixed_form(double v, int decimals) {
  return trim_fraction(fmt::format("{:.{}f}", v, std::clamp(decimals, 0, 17)));
}

double pow10i(int e) {
  return std::pow(10.0, e);
}

// k * 10^e, rounded once (so that 3 * 10^-1 is the double nearest 0.3).
double scaled(double k, int e) {
  return (e >= 0 ? k * pow10i(e) : k / pow10i(-e)) + 0.0;
}

// Widens a zero-width (or non-finite) range so it can be drawn.
void pad_if_flat(double& lo, double& hi) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) {
    lo = 0;
    hi = 1;
  }
  if (lo > hi) std::swap(lo, hi);
  const double mag = std::max(std::fabs(lo), std::fabs(hi));
  if (hi - lo <= mag * 1e-12) {
    const double c = 0.5 * (lo + hi);
    const double p = c != 0 ? std::fabs(c) * 0.05 : 1.0;
    lo = c - p;
    hi = c + p;
  }
}

// ---------------------------------------------------------------------------------------------
// Axes

// One axis: its range and ticks in "transformed" space (log10 of the value on a log axis).
struct Axis {
  bool log = false;
  double lo = 0, hi = 1;           // transformed range
  std::vector<double> major;       // transformed positions of labelled ticks
  std::vector<std::string> labels; // one per major tick
  std::vector<double> minor;       // transformed positions of unlabelled grid lines
  double p0 = 0, p1 = 1;           // pixel positions of lo and hi

  double transform(double v) const {
    if (!log) return v;
    return v > 0 ? std::log10(v) : kNaN;
  }
  // Pixel position of a transformed value.
  double pixel_t(double t) const { return p0 + (t - lo) / (hi - lo) * (p1 - p0); }
  // Pixel position of a data value (NaN if it cannot be shown), clamped to a sane magnitude.
  double pixel(double v) const {
    const double t = transform(v);
    if (!std::isfinite(t)) return kNaN;
    return std::clamp(pixel_t(t), -1e6, 1e6);
  }
};

// Which tick steps an axis may use: 1-2-5 x 10^k, or for time axes also steps that divide
// hours (15 min, 30 min) and days (3 h, 6 h, 12 h, 24 h, 1 week).
enum class StepSet { decimal, minutes, hours };

Ticks make_ticks(double lo, double hi, int max_ticks, StepSet set) {
  lo = std::clamp(std::isfinite(lo) ? lo : 0.0, -1e300, 1e300);
  hi = std::clamp(std::isfinite(hi) ? hi : 1.0, -1e300, 1e300);
  pad_if_flat(lo, hi);
  max_ticks = std::max(max_ticks, 2);
  const double span = hi - lo;
  const int e0 = static_cast<int>(std::floor(std::log10(span / (max_ticks - 1)))) - 1;
  struct Step {
    double m; // step = m * 10^e
    int e;
    double value() const { return scaled(m, e); }
  };
  std::vector<Step> steps;
  for (int e = e0; e < e0 + 64; ++e)
    for (const double m : {1.0, 2.0, 5.0})
      steps.push_back({m, e});
  if (set != StepSet::decimal) {
    const double custom_end = set == StepSet::hours ? 1000 : 100;
    std::erase_if(steps, [&](const Step& s) { return s.value() >= 1 && s.value() < custom_end; });
    const std::vector<double> custom =
        set == StepSet::hours
            ? std::vector<double>{1, 2, 3, 6, 12, 24, 48, 72, 96, 168, 336, 504, 672}
            : std::vector<double>{1, 2, 5, 10, 15, 20, 30, 60};
    for (const double m : custom)
      steps.push_back({m, 0});
    std::stable_sort(steps.begin(), steps.end(),
                     [](const Step& x, const Step& y) { return x.value() < y.value(); });
  }
  // Round-off allowance, so that 0.3 counts as a multiple of 0.1.
  const double slack = 1e-9 * span + 1e-14 * std::max(std::fabs(lo), std::fabs(hi));
  for (const Step& s : steps) {
    const double step = s.value();
    if (!std::isfinite(step)) break;
    const double a = std::floor((lo + slack) / step);
    const double b = std::ceil((hi - slack) / step);
    if (b - a + 1 > max_ticks) continue;
    Ticks t;
    t.step = step;
    for (double k = a; k <= b; k += 1)
      t.values.push_back(scaled(k * s.m, s.e));
    return t;
  }
  // Two ticks cannot cover a range around a multiple of every step (e.g. -1..3): allow three.
  if (max_ticks < 3) return make_ticks(lo, hi, 3, set);
  return Ticks{{lo, hi}, hi - lo}; // not reached for finite input
}

enum class Fit {
  extend, // the range grows to the outermost ticks
  snap,   // the range grows to a tick only when it is within 5 % of the span
  fixed   // the range is kept
};

Axis linear_axis(double lo, double hi, Fit fit, int max_ticks, StepSet set) {
  pad_if_flat(lo, hi);
  Axis a;
  if (fit == Fit::extend) {
    const Ticks t = make_ticks(lo, hi, max_ticks, set);
    a.lo = t.values.front();
    a.hi = t.values.back();
    a.major = t.values;
    a.labels = tick_labels(t);
    return a;
  }
  // Ticks inside a kept range are fewer than around it: take the densest set that fits.
  const double span = hi - lo;
  for (int mt = max_ticks + 4;; --mt) {
    Ticks t = make_ticks(lo, hi, mt, set);
    double l = lo, h = hi;
    if (fit == Fit::snap) {
      if (t.values.front() >= lo - 0.05 * span) l = t.values.front();
      if (t.values.back() <= hi + 0.05 * span) h = t.values.back();
    }
    const double eps = t.step * 1e-9;
    std::erase_if(t.values, [&](double v) { return v < l - eps || v > h + eps; });
    if (static_cast<int>(t.values.size()) <= max_ticks || mt <= 2) {
      a.lo = l;
      a.hi = h;
      a.major = t.values;
      a.labels = tick_labels(t);
      return a;
    }
  }
}

// lo, hi > 0 in data space.
Axis log_axis(double lo, double hi, Fit fit, int max_ticks) {
  Axis a;
  a.log = true;
  double l = std::log10(lo), h = std::log10(hi);
  if (!std::isfinite(l) || !std::isfinite(h)) {
    l = 0;
    h = 1;
  }
  if (l > h) std::swap(l, h);
  if (h - l < 1e-9) {
    l -= 0.5;
    h += 0.5;
  }
  const double fl = std::floor(l + 1e-9), ch = std::ceil(h - 1e-9);
  const double near = 0.1 * std::max(h - l, 1.0);
  if (fit == Fit::extend || (fit == Fit::snap && l - fl <= near)) l = fl;
  if (fit == Fit::extend || (fit == Fit::snap && ch - h <= near)) h = ch;
  a.lo = l;
  a.hi = h;
  const int first = static_cast<int>(std::ceil(l - 1e-9));
  const int last = static_cast<int>(std::floor(h + 1e-9));
  const int decades = last - first + 1;
  int stride = 1;
  for (const int s : {1, 2, 3, 5, 10, 20, 50, 100}) {
    stride = s;
    if ((decades + s - 1) / s <= std::max(max_ticks, 2)) break;
  }
  struct Tick {
    double t;
    std::string label;
  };
  std::vector<Tick> ticks;
  for (int k = first; k <= last; ++k) {
    if ((k - first) % stride != 0) continue;
    ticks.push_back({static_cast<double>(k), format_number(pow10i(k), 6)});
  }
  if (stride == 1 && h - l <= 8) {
    const bool label_2_5 = ticks.size() < 3;
    for (int k = static_cast<int>(std::floor(l)) - 1; k <= static_cast<int>(std::ceil(h)); ++k) {
      for (int m = 2; m <= 9; ++m) {
        const double t = k + std::log10(static_cast<double>(m));
        if (t < l - 1e-9 || t > h + 1e-9) continue;
        if (label_2_5 && (m == 2 || m == 5))
          ticks.push_back({t, format_number(m * pow10i(k), 6)});
        else
          a.minor.push_back(t);
      }
    }
  }
  std::sort(ticks.begin(), ticks.end(), [](const Tick& x, const Tick& y) { return x.t < y.t; });
  for (auto& t : ticks) {
    a.major.push_back(t.t);
    a.labels.push_back(std::move(t.label));
  }
  return a;
}

Axis make_axis(bool log, double dlo, double dhi,
               const std::optional<std::pair<double, double>>& fixed, double fixed_divisor, Fit fit,
               int max_ticks, StepSet set) {
  if (fixed) {
    double lo = fixed->first / fixed_divisor, hi = fixed->second / fixed_divisor;
    if (std::isfinite(lo) && std::isfinite(hi) && (!log || (lo > 0 && hi > 0)))
      return log ? log_axis(lo, hi, Fit::fixed, max_ticks)
                 : linear_axis(lo, hi, Fit::fixed, max_ticks, set);
  }
  return log ? log_axis(dlo, dhi, fit, max_ticks) : linear_axis(dlo, dhi, fit, max_ticks, set);
}

double max_label_width(const Axis& a, double font) {
  double w = 0;
  for (const auto& s : a.labels)
    w = std::max(w, text_width(s, font));
  return w;
}

// Smallest pixel distance between neighbouring labelled ticks (infinite with fewer than two).
double min_tick_gap(const Axis& a) {
  double gap = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < a.major.size(); ++i)
    gap = std::min(gap, std::fabs(a.pixel_t(a.major[i]) - a.pixel_t(a.major[i - 1])));
  return gap;
}

// ---------------------------------------------------------------------------------------------
// Output helpers

struct Out {
  std::string s;
  template <typename... A> void f(fmt::format_string<A...> fs, A&&... a) {
    fmt::format_to(std::back_inserter(s), fs, std::forward<A>(a)...);
  }
  // A coordinate rounded to 0.1 px, without a trailing ".0".
  void num(double v) {
    long long t = std::isfinite(v) ? std::llround(std::clamp(v, -1e6, 1e6) * 10) : 0;
    if (t < 0) {
      s += '-';
      t = -t;
    }
    fmt::format_to(std::back_inserter(s), "{}", t / 10);
    if (t % 10 != 0) {
      s += '.';
      s += static_cast<char>('0' + t % 10);
    }
  }
  void text(std::string_view sanitized) { append_escaped(s, sanitized); }
};

std::string n1(double v) {
  Out o;
  o.num(v);
  return o.s;
}

struct Pt {
  double x, y;
};

struct Rect {
  double x, y, w, h;
  double right() const { return x + w; }
  double bottom() const { return y + h; }
};

// Tenths of a pixel, for dropping repeated points.
long long tenths(double v) {
  return std::isfinite(v) ? std::llround(std::clamp(v, -1e6, 1e6) * 10) : 0;
}

// Appends polylines as one path data string: "M x y L x y x y ..." per segment.
void append_polylines(Out& o, const std::vector<std::vector<Pt>>& segs) {
  for (const auto& seg : segs) {
    long long lx = LLONG_MIN, ly = LLONG_MIN;
    std::size_t emitted = 0;
    for (const Pt& p : seg) {
      const long long tx = tenths(p.x), ty = tenths(p.y);
      if (tx == lx && ty == ly) continue;
      o.s += emitted == 0 ? "M" : emitted == 1 ? "L" : " ";
      o.num(p.x);
      o.s += ' ';
      o.num(p.y);
      lx = tx;
      ly = ty;
      ++emitted;
    }
  }
}

// Appends closed polygons as one path data string.
void append_polygons(Out& o, const std::vector<std::vector<Pt>>& polys) {
  for (const auto& poly : polys) {
    append_polylines(o, {poly});
    o.s += 'Z';
  }
}

// Appends one marker of the given shape (0 circle, 1 square, 2 diamond, 3 triangle) at p.
void append_marker(Out& o, Pt p, int shape, double r) {
  switch (shape % 4) {
  case 0:
    o.s += 'M';
    o.num(p.x - r);
    o.s += ' ';
    o.num(p.y);
    o.f("a{0} {0} 0 1 0 {1} 0a{0} {0} 0 1 0 -{1} 0", n1(r), n1(2 * r));
    break;
  case 1: {
    const double h = r * 0.85;
    o.s += 'M';
    o.num(p.x - h);
    o.s += ' ';
    o.num(p.y - h);
    o.f("h{0}v{0}h-{0}z", n1(2 * h));
    break;
  }
  case 2:
    o.s += 'M';
    o.num(p.x);
    o.s += ' ';
    o.num(p.y - r * 1.15);
    o.f("l{0} {0} -{0} {0} -{0} -{0}z", n1(r * 1.15));
    break;
  default:
    o.s += 'M';
    o.num(p.x);
    o.s += ' ';
    o.num(p.y - r * 1.15);
    o.f("l{} {}h-{}z", n1(r * 1.1), n1(r * 1.9), n1(r * 2.2));
  }
}

// ---------------------------------------------------------------------------------------------
// Geometry: data to pixel polylines, with gaps and per-column decimation.

struct Mapping {
  const Axis* xa;
  const Axis* ya;
  double divisor;
  Rect plot;
  bool at(double x, double y, Pt& p) const {
    if (!std::isfinite(x) || !std::isfinite(y)) return false;
    p.x = xa->pixel(x / divisor);
    p.y = ya->pixel(y);
    return std::isfinite(p.x) && std::isfinite(p.y);
  }
  long long column(double px) const {
    return static_cast<long long>(std::floor(std::clamp(px - plot.x, -1.0, plot.w + 1.0)));
  }
};

// Series data as pixel polylines. Small series keep every point; large ones (more than two points
// per pixel column) keep, per column, the first, lowest, highest and last point, so peaks survive
// and the size is bounded; gaps narrower than a column are then ignored.
std::vector<std::vector<Pt>> raw_segments(const Series& s, const Mapping& m) {
  const std::size_t n = std::min(s.x.size(), s.y.size());
  std::vector<std::vector<Pt>> segs;
  std::vector<Pt> cur;
  auto end_segment = [&] {
    if (!cur.empty()) segs.push_back(std::move(cur));
    cur.clear();
  };
  const double columns = std::max(1.0, std::ceil(m.plot.w));
  const bool decimate = static_cast<double>(n) > 2 * columns + 16;
  if (!decimate) {
    for (std::size_t i = 0; i < n; ++i) {
      Pt p{};
      if (!m.at(s.x[i], s.y[i], p)) {
        end_segment();
        continue;
      }
      cur.push_back(p);
    }
    end_segment();
    return segs;
  }
  struct Bucket {
    bool any = false;
    long long col = 0;
    std::size_t i_first = 0, i_min = 0, i_max = 0, i_last = 0;
    Pt first{}, min{}, max{}, last{};
  } b;
  auto flush = [&] {
    if (!b.any) return;
    std::array<std::pair<std::size_t, Pt>, 4> pts = {
        {{b.i_first, b.first}, {b.i_min, b.min}, {b.i_max, b.max}, {b.i_last, b.last}}};
    std::sort(pts.begin(), pts.end(),
              [](const auto& a, const auto& c) { return a.first < c.first; });
    for (std::size_t k = 0; k < pts.size(); ++k)
      if (k == 0 || pts[k].first != pts[k - 1].first) cur.push_back(pts[k].second);
    b.any = false;
  };
  bool gap = false;
  long long last_col = LLONG_MIN;
  for (std::size_t i = 0; i < n; ++i) {
    Pt p{};
    if (!m.at(s.x[i], s.y[i], p)) {
      gap = true;
      continue;
    }
    const long long col = m.column(p.x);
    if (gap) {
      gap = false;
      if (col != last_col) {
        flush();
        end_segment();
      }
    }
    if (b.any && col != b.col) flush();
    if (!b.any) {
      b.any = true;
      b.col = col;
      b.i_first = b.i_min = b.i_max = i;
      b.first = b.min = b.max = p;
    } else if (p.y < b.min.y) {
      b.i_min = i;
      b.min = p;
    } else if (p.y > b.max.y) {
      b.i_max = i;
      b.max = p;
    }
    b.i_last = i;
    b.last = p;
    last_col = col;
  }
  flush();
  end_segment();

  // x not increasing (e.g. a parametric curve) defeats the columns: thin out evenly as a last
  // resort so the output stays bounded.
  const auto cap = static_cast<std::size_t>(8 * columns + 64);
  std::size_t total = 0;
  for (const auto& seg : segs)
    total += seg.size();
  if (total > cap) {
    const std::size_t stride = (total + cap - 1) / cap;
    std::vector<std::vector<Pt>> thin;
    std::size_t k = 0;
    for (const auto& seg : segs) {
      std::vector<Pt> t;
      for (const Pt& p : seg)
        if (k++ % stride == 0) t.push_back(p);
      if (!t.empty()) thin.push_back(std::move(t));
    }
    segs = std::move(thin);
  }
  return segs;
}

// Drops points closer than tol px to the polyline through the kept ones (Douglas-Peucker).
std::vector<Pt> simplify(const std::vector<Pt>& pts, double tol) {
  const std::size_t n = pts.size();
  if (n < 3) return pts;
  std::vector<char> keep(n, 0);
  keep[0] = keep[n - 1] = 1;
  std::vector<std::pair<std::size_t, std::size_t>> todo{{0, n - 1}};
  while (!todo.empty()) {
    const auto [a, b] = todo.back();
    todo.pop_back();
    if (b <= a + 1) continue;
    const double dx = pts[b].x - pts[a].x, dy = pts[b].y - pts[a].y;
    const double len2 = dx * dx + dy * dy;
    double worst = -1;
    std::size_t at = a;
    for (std::size_t i = a + 1; i < b; ++i) {
      // Distance to the segment (not the line), so that back-and-forth spikes are kept.
      double t = len2 > 0 ? ((pts[i].x - pts[a].x) * dx + (pts[i].y - pts[a].y) * dy) / len2 : 0;
      t = std::clamp(t, 0.0, 1.0);
      const double ex = pts[a].x + t * dx - pts[i].x, ey = pts[a].y + t * dy - pts[i].y;
      const double d2 = ex * ex + ey * ey;
      if (d2 > worst) {
        worst = d2;
        at = i;
      }
    }
    if (worst > tol * tol) {
      keep[at] = 1;
      todo.push_back({a, at});
      todo.push_back({at, b});
    }
  }
  std::vector<Pt> out;
  for (std::size_t i = 0; i < n; ++i)
    if (keep[i]) out.push_back(pts[i]);
  return out;
}

// Series data as pixel polylines, decimated and then simplified to within 0.2 px.
std::vector<std::vector<Pt>> line_segments(const Series& s, const Mapping& m) {
  std::vector<std::vector<Pt>> segs = raw_segments(s, m);
  for (auto& seg : segs)
    seg = simplify(seg, 0.2);
  return segs;
}

// Marker positions inside (or just outside) the plot; dense data keeps one marker per cell of
// about a marker's size.
std::vector<Pt> marker_points(const Series& s, const Mapping& m) {
  const std::size_t n = std::min(s.x.size(), s.y.size());
  const double margin = kMarkerRadius + 2;
  const bool dense = static_cast<double>(n) > 2 * std::max(1.0, m.plot.w);
  std::unordered_set<long long> used;
  std::vector<Pt> pts;
  const double cell = 2 * kMarkerRadius;
  for (std::size_t i = 0; i < n; ++i) {
    Pt p{};
    if (!m.at(s.x[i], s.y[i], p)) continue;
    if (p.x < m.plot.x - margin || p.x > m.plot.right() + margin || p.y < m.plot.y - margin ||
        p.y > m.plot.bottom() + margin)
      continue;
    if (dense) {
      const auto cx = static_cast<long long>(std::floor((p.x - m.plot.x + margin) / cell));
      const auto cy = static_cast<long long>(std::floor((p.y - m.plot.y + margin) / cell));
      if (!used.insert(cx * 1000003LL + cy).second) continue;
    }
    pts.push_back(p);
  }
  return pts;
}

// Band outlines: per run of finite points, the upper edge forward and the lower edge backward.
std::vector<std::vector<Pt>> band_polygons(const Band& b, const Mapping& m) {
  const std::size_t n = std::min({b.x.size(), b.lo.size(), b.hi.size()});
  const double columns = std::max(1.0, std::ceil(m.plot.w));
  const bool decimate = static_cast<double>(n) > 2 * columns + 16;
  std::vector<std::vector<Pt>> polys;
  std::vector<Pt> upper, lower;
  auto end_run = [&] {
    if (!upper.empty()) {
      std::vector<Pt> poly = upper;
      poly.insert(poly.end(), lower.rbegin(), lower.rend());
      polys.push_back(std::move(poly));
    }
    upper.clear();
    lower.clear();
  };
  bool gap = false;
  long long col_cur = LLONG_MIN;
  for (std::size_t i = 0; i < n; ++i) {
    Pt ph{}, pl{};
    if (!m.at(b.x[i], b.hi[i], ph) || !m.at(b.x[i], b.lo[i], pl)) {
      gap = true;
      continue;
    }
    if (ph.y > pl.y) std::swap(ph.y, pl.y); // upper edge: smaller pixel y
    if (decimate) {
      const long long col = m.column(ph.x);
      if (gap && col != col_cur) end_run();
      gap = false;
      if (!upper.empty() && col == col_cur) {
        upper.back().y = std::min(upper.back().y, ph.y);
        lower.back().y = std::max(lower.back().y, pl.y);
        continue;
      }
      col_cur = col;
    } else if (gap) {
      end_run();
      gap = false;
    }
    upper.push_back(ph);
    lower.push_back(pl);
  }
  end_run();
  return polys;
}

// ---------------------------------------------------------------------------------------------
// Legend

enum class Swatch { line, markers, line_markers, band };

struct Style {
  std::string color;
  std::string dash; // stroke-dasharray ("" for solid)
  int shape = 0;    // marker shape
  bool line = true;
  bool markers = false;
};

struct LegendEntry {
  std::string label; // sanitised
  Style style;
  double width = 1.5;
  bool band = false;
};

struct LegendLayout {
  double width = 0; // including the gap before it
  double font = 12;
  double line_height = 16;
  double column_width = 0;
  int columns = 0;
  int rows = 0;
  std::size_t shown = 0;  // entries drawn (the rest summarised as "+N more")
  double label_width = 0; // labels cut to this width in px
};

constexpr double kSwatchWidth = 26;  // swatch plus gap before the text
constexpr double kLegendGap = 18;    // between the plot area and the legend
constexpr double kLegendColGap = 12; // between legend columns

// Chooses font size, columns and label width so the legend fits `height` and `max_width`:
// first whole labels (shrinking the font, then wrapping into columns), then labels cut to no
// less than 10 average characters, and at last a "+N more" line for what does not fit.
LegendLayout layout_legend(const std::vector<LegendEntry>& entries, double height,
                           double max_width) {
  LegendLayout L;
  if (entries.empty()) return L;
  const std::size_t n = entries.size();
  double longest_em = 0; // widest label at 1 px font size
  for (const auto& e : entries)
    longest_em = std::max(longest_em, text_width(e.label, 1.0));
  auto finish = [&](double fs, int cols, std::size_t shown, double label_w) {
    L.font = fs;
    L.line_height = std::round(fs * 1.4);
    L.columns = cols;
    L.shown = shown;
    const std::size_t slots = shown < n ? shown + 1 : shown;
    L.rows = static_cast<int>((slots + static_cast<std::size_t>(cols) - 1) /
                              static_cast<std::size_t>(cols));
    L.label_width = label_w;
    L.column_width = kSwatchWidth + label_w + kLegendColGap;
    L.width = kLegendGap + cols * L.column_width - kLegendColGap;
    return L;
  };
  for (int pass = 0; pass < 2; ++pass) {
    for (int cols = 1; cols <= 6; ++cols) {
      for (const double fs : {12.0, 11.0, 10.0, 9.0}) {
        const double lh = std::round(fs * 1.4);
        const auto rows = static_cast<std::size_t>(std::max(1.0, std::floor(height / lh)));
        if (rows * static_cast<std::size_t>(cols) < n) continue;
        const double avail = (max_width - kLegendGap) / cols - kLegendColGap - kSwatchWidth;
        const double longest = longest_em * fs;
        if (longest <= avail) return finish(fs, cols, n, longest);
        if (pass == 1 && avail >= std::min(longest, 10 * 0.6 * fs))
          return finish(fs, cols, n, avail);
      }
    }
  }
  const double fs = 9, lh = std::round(fs * 1.4);
  const double label_w = std::min(longest_em * fs, 10 * 0.6 * fs);
  const int cols = std::max(1, static_cast<int>((max_width - kLegendGap + kLegendColGap) /
                                                (kSwatchWidth + label_w + kLegendColGap)));
  const auto rows = static_cast<std::size_t>(std::max(1.0, std::floor(height / lh)));
  const std::size_t slots = rows * static_cast<std::size_t>(cols);
  return finish(fs, cols, slots > 1 ? std::min(n, slots - 1) : 0, label_w);
}

void draw_swatch(Out& o, const LegendEntry& e, double x, double y_mid) {
  if (e.band) {
    o.f(R"(<rect x="{}" y="{}" width="20" height="10" fill="{}" fill-opacity="0.25" stroke="{}" )"
        R"(stroke-opacity="0.6" stroke-width="0.8"/>)",
        n1(x), n1(y_mid - 5), e.style.color, e.style.color);
    return;
  }
  if (e.style.line) {
    o.f(R"(<path d="M{} {}h20" fill="none" stroke="{}" stroke-width="{}" stroke-linecap="round")",
        n1(x), n1(y_mid), e.style.color, n1(e.width));
    if (!e.style.dash.empty()) o.f(R"( stroke-dasharray="{}")", e.style.dash);
    o.s += "/>";
  }
  if (e.style.markers) {
    o.s += R"(<path d=")";
    append_marker(o, {x + 10, y_mid}, e.style.shape, kMarkerRadius);
    o.f(R"(" fill="none" stroke="{}" stroke-width="1.2"/>)", e.style.color);
  }
}

void draw_legend(Out& o, const std::vector<LegendEntry>& entries, const LegendLayout& L, double x0,
                 double y0) {
  if (entries.empty()) return;
  o.f(R"(<g class="legend" font-size="{}" fill="#222222">)", n1(L.font));
  const std::size_t slots = L.shown < entries.size() ? L.shown + 1 : L.shown;
  for (std::size_t i = 0; i < slots; ++i) {
    const auto col = static_cast<double>(i / static_cast<std::size_t>(L.rows));
    const auto row = static_cast<double>(i % static_cast<std::size_t>(L.rows));
    const double x = x0 + col * L.column_width;
    const double y_mid = y0 + row * L.line_height + L.line_height / 2;
    const double baseline = y_mid + L.font * 0.35;
    if (i == L.shown) {
      o.f(R"(<text x="{}" y="{}" fill="#666666">+{} more</text>)", n1(x), n1(baseline),
          entries.size() - L.shown);
      break;
    }
    const LegendEntry& e = entries[i];
    o.s += R"(<g class="legend-entry">)";
    draw_swatch(o, e, x, y_mid);
    o.f(R"(<text x="{}" y="{}">)", n1(x + kSwatchWidth), n1(baseline));
    o.text(truncate(e.label, L.label_width + 0.5, L.font));
    o.s += "</text></g>";
  }
  o.s += "</g>\n";
}

// ---------------------------------------------------------------------------------------------
// Panels

Style series_style(const Series& s, int color_index) {
  Style st;
  const int n = palette_size();
  st.color = palette_color(color_index);
  const int round = color_index / n;
  st.shape = round % 4;
  st.line = s.style != LineStyle::markers;
  st.markers = s.style == LineStyle::markers || s.style == LineStyle::markers_line;
  switch (s.style) {
  case LineStyle::solid:
    st.dash = kDashCycle[static_cast<std::size_t>(round) % kDashCycle.size()];
    break;
  case LineStyle::dashed:
    st.dash = kDashed;
    break;
  case LineStyle::dotted:
    st.dash = kDotted;
    break;
  case LineStyle::dash_dot:
    st.dash = kDashDot;
    break;
  default:
    break;
  }
  return st;
}

// Stroke width of a series, kept within 0.5..4 px.
double line_width_of(const Series& s) {
  return std::isfinite(s.line_width) ? std::clamp(s.line_width, 0.5, 4.0) : 1.5;
}

struct DataRange {
  double xlo = std::numeric_limits<double>::infinity(), xhi = -xlo;
  double ylo = xlo, yhi = -xlo;
  bool any() const { return xlo <= xhi; }
};

void render_panel(Out& o, const Panel& p, int index, Rect cell) {
  // Time axis: choose the unit from the largest time shown.
  double divisor = 1;
  StepSet x_steps = StepSet::decimal;
  std::string x_label = sanitize(p.x_label);
  if (p.x_is_time_s) {
    double t_max = 0;
    auto scan = [&](const std::vector<double>& xs) {
      for (const double v : xs)
        if (std::isfinite(v)) t_max = std::max(t_max, std::fabs(v));
    };
    for (const auto& s : p.series)
      scan(s.x);
    for (const auto& b : p.bands)
      scan(b.x);
    if (p.x_range) {
      for (const double v : {p.x_range->first, p.x_range->second})
        if (std::isfinite(v)) t_max = std::max(t_max, std::fabs(v));
    }
    const TimeAxis ta = choose_time_axis(t_max);
    divisor = ta.divisor;
    x_steps = ta.unit == "h"     ? StepSet::hours
              : ta.unit == "min" ? StepSet::minutes
                                 : StepSet::decimal;
    x_label = x_label.empty() ? fmt::format("time [{}]", ta.unit)
                              : fmt::format("{} [{}]", x_label, ta.unit);
  }

  // Data ranges (in the displayed unit), skipping what cannot be drawn.
  DataRange r;
  auto add = [&](double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    x /= divisor;
    if ((p.log_x && x <= 0) || (p.log_y && y <= 0)) return;
    r.xlo = std::min(r.xlo, x);
    r.xhi = std::max(r.xhi, x);
    r.ylo = std::min(r.ylo, y);
    r.yhi = std::max(r.yhi, y);
  };
  for (const auto& s : p.series) {
    const std::size_t n = std::min(s.x.size(), s.y.size());
    for (std::size_t i = 0; i < n; ++i)
      add(s.x[i], s.y[i]);
  }
  for (const auto& b : p.bands) {
    const std::size_t n = std::min({b.x.size(), b.lo.size(), b.hi.size()});
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(b.lo[i]) || !std::isfinite(b.hi[i])) continue;
      add(b.x[i], b.lo[i]);
      add(b.x[i], b.hi[i]);
    }
  }
  const bool has_data = r.any();
  if (!has_data) {
    r.xlo = p.log_x ? 1 : 0;
    r.xhi = p.log_x ? 10 : 1;
    r.ylo = p.log_y ? 1 : 0;
    r.yhi = p.log_y ? 10 : 1;
  }

  // Styles and legend entries.
  std::vector<Style> sstyles;
  std::vector<LegendEntry> entries;
  int auto_series = 0, auto_band = 0;
  for (const auto& s : p.series) {
    const int ci = s.color >= 0 ? s.color : auto_series++;
    sstyles.push_back(series_style(s, ci));
    if (!s.label.empty())
      entries.push_back({sanitize(s.label), sstyles.back(), line_width_of(s), false});
  }
  std::vector<std::string> bcolors;
  for (const auto& b : p.bands) {
    const int ci = b.color >= 0 ? b.color : auto_band++;
    bcolors.push_back(palette_color(ci));
    if (!b.label.empty()) {
      LegendEntry e;
      e.label = sanitize(b.label);
      e.style.color = bcolors.back();
      e.band = true;
      entries.push_back(std::move(e));
    }
  }

  // Vertical layout.
  const std::string title = sanitize(p.title);
  const std::string y_label = sanitize(p.y_label);
  double top = cell.y + 8;
  const double title_baseline = top + kPanelTitleFont;
  if (!title.empty()) top += kPanelTitleFont + 8;
  const double plot_top = top + 8;
  const double plot_bottom =
      cell.bottom() - 8 - (x_label.empty() ? 0 : kLabelFont + 8) - kTickFont - 8;
  const double plot_h = std::max(40.0, plot_bottom - plot_top);

  // y axis first: its labels set the left margin.
  Axis ya = make_axis(p.log_y, r.ylo, r.yhi, p.y_range, 1.0, Fit::extend,
                      std::clamp(static_cast<int>(plot_h / 40), 2, 10), StepSet::decimal);
  const double left =
      8 + (y_label.empty() ? 0 : kLabelFont + 8) + max_label_width(ya, kTickFont) + 8;

  const LegendLayout L =
      layout_legend(entries, plot_h, std::min(0.42 * cell.w, std::max(0.3 * cell.w, 260.0)));
  const double right = entries.empty() ? 24 : 10 + L.width;
  Rect plot{cell.x + left, plot_top, std::max(40.0, cell.w - left - right), plot_h};
  ya.p0 = plot.bottom();
  ya.p1 = plot.y;

  Axis xa;
  for (int mt = std::clamp(static_cast<int>(plot.w / 45), 2, 12);; --mt) {
    xa = make_axis(p.log_x, r.xlo, r.xhi, p.x_range, divisor, Fit::snap, mt, x_steps);
    xa.p0 = plot.x;
    xa.p1 = plot.right();
    if (mt <= 2 || min_tick_gap(xa) >= max_label_width(xa, kTickFont) + 10) break;
  }

  o.f("<g class=\"panel\">\n");
  o.f(R"(<clipPath id="clip{}"><rect x="{}" y="{}" width="{}" height="{}"/></clipPath>)", index,
      n1(plot.x - kMarkerRadius - 1), n1(plot.y - kMarkerRadius - 1),
      n1(plot.w + 2 * kMarkerRadius + 2), n1(plot.h + 2 * kMarkerRadius + 2));
  o.s += '\n';

  // Grid: minor (log axes), major, then a zero line.
  auto grid = [&](const std::vector<double>& xs, const std::vector<double>& ys, const char* color) {
    Out d;
    for (const double t : xs) {
      const double px = std::round(xa.pixel_t(t)) + 0.5;
      if (px <= plot.x + 1 || px >= plot.right() - 1) continue;
      d.s += 'M';
      d.num(px);
      d.s += ' ';
      d.num(plot.y);
      d.s += 'V';
      d.num(plot.bottom());
    }
    for (const double t : ys) {
      const double py = std::round(ya.pixel_t(t)) + 0.5;
      if (py <= plot.y + 1 || py >= plot.bottom() - 1) continue;
      d.s += 'M';
      d.num(plot.x);
      d.s += ' ';
      d.num(py);
      d.s += 'H';
      d.num(plot.right());
    }
    if (!d.s.empty())
      o.f(R"(<path class="grid" d="{}" fill="none" stroke="{}" stroke-width="1"/>)"
          "\n",
          d.s, color);
  };
  // Minor grid lines of log axes only where decades are wide enough to show them clearly.
  if (std::fabs(xa.pixel_t(1) - xa.pixel_t(0)) < 80) xa.minor.clear();
  if (std::fabs(ya.pixel_t(1) - ya.pixel_t(0)) < 80) ya.minor.clear();
  grid(xa.minor, ya.minor, "#eeeeee");
  grid(xa.major, ya.major, "#dcdcdc");
  if (!ya.log && ya.lo < 0 && ya.hi > 0) grid({}, {0.0}, "#a8a8a8");

  // Frame and tick marks.
  o.f(R"(<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#8c8c8c" stroke-width="1"/>)"
      "\n",
      n1(plot.x), n1(plot.y), n1(plot.w), n1(plot.h));
  {
    Out d;
    for (const double t : xa.major) {
      d.s += 'M';
      d.num(xa.pixel_t(t));
      d.s += ' ';
      d.num(plot.bottom());
      d.s += "v4";
    }
    for (const double t : ya.major) {
      d.s += 'M';
      d.num(plot.x);
      d.s += ' ';
      d.num(ya.pixel_t(t));
      d.s += "h-4";
    }
    if (!d.s.empty())
      o.f(R"(<path d="{}" fill="none" stroke="#8c8c8c" stroke-width="1"/>)"
          "\n",
          d.s);
  }

  // Tick labels.
  o.f(R"(<g font-size="{}" fill="#333333">)", n1(kTickFont));
  for (std::size_t i = 0; i < xa.major.size(); ++i) {
    o.f(R"(<text x="{}" y="{}" text-anchor="middle">)", n1(xa.pixel_t(xa.major[i])),
        n1(plot.bottom() + 6 + kTickFont));
    o.text(xa.labels[i]);
    o.s += "</text>";
  }
  for (std::size_t i = 0; i < ya.major.size(); ++i) {
    o.f(R"(<text x="{}" y="{}" text-anchor="end">)", n1(plot.x - 7),
        n1(ya.pixel_t(ya.major[i]) + kTickFont * 0.35));
    o.text(ya.labels[i]);
    o.s += "</text>";
  }
  o.s += "</g>\n";

  // Axis labels and title.
  if (!x_label.empty()) {
    o.f(R"(<text x="{}" y="{}" text-anchor="middle" font-size="{}" fill="#222222">)",
        n1(plot.x + plot.w / 2), n1(plot.bottom() + 6 + kTickFont + 8 + kLabelFont),
        n1(kLabelFont));
    o.text(fit_text(x_label, plot.w, kLabelFont));
    o.s += "</text>\n";
  }
  if (!y_label.empty()) {
    const double x = cell.x + 8 + kLabelFont;
    const double y = plot.y + plot.h / 2;
    o.f(R"~(<text x="{0}" y="{1}" transform="rotate(-90 {0} {1})" text-anchor="middle" font-size="{2}" )~"
        R"(fill="#222222">)",
        n1(x), n1(y), n1(kLabelFont));
    o.text(fit_text(y_label, plot.h, kLabelFont));
    o.s += "</text>\n";
  }
  if (!title.empty()) {
    // Centred over the plot area when it fits there, else shifted (and cut) to stay in the cell.
    const std::string shown = fit_text(title, cell.w - 16, kPanelTitleFont, true);
    const double half = 0.55 * text_width(shown, kPanelTitleFont);
    const double cx = std::clamp(plot.x + plot.w / 2, cell.x + 8 + half,
                                 std::max(cell.x + 8 + half, cell.right() - 8 - half));
    o.f(R"(<text x="{}" y="{}" text-anchor="middle" font-size="{}" font-weight="bold" fill="#111111">)",
        n1(cx), n1(title_baseline), n1(kPanelTitleFont));
    o.text(shown);
    o.s += "</text>\n";
  }
  if (!has_data) {
    o.f(R"(<text x="{}" y="{}" text-anchor="middle" font-size="{}" fill="#999999">no data</text>)"
        "\n",
        n1(plot.x + plot.w / 2), n1(plot.y + plot.h / 2), n1(kLabelFont));
  }

  // Data, clipped to the plot area.
  const Mapping m{&xa, &ya, divisor, plot};
  o.f(R"~(<g clip-path="url(#clip{})">)~"
      "\n",
      index);
  for (std::size_t k = 0; k < p.bands.size(); ++k) {
    const auto polys = band_polygons(p.bands[k], m);
    if (polys.empty()) continue;
    Out d;
    append_polygons(d, polys);
    o.f(R"(<path class="band" d="{}" fill="{}" fill-opacity="0.2" stroke="{}" stroke-opacity="0.45" )"
        R"(stroke-width="0.8" stroke-linejoin="round"/>)"
        "\n",
        d.s, bcolors[k], bcolors[k]);
  }
  for (std::size_t k = 0; k < p.series.size(); ++k) {
    const Series& s = p.series[k];
    const Style& st = sstyles[k];
    const double lw = line_width_of(s);
    if (st.line) {
      const auto segs = line_segments(s, m);
      Out d;
      append_polylines(d, segs);
      if (!d.s.empty()) {
        o.f(R"(<path class="series" d="{}" fill="none" stroke="{}" stroke-width="{}" )"
            R"(stroke-linejoin="round" stroke-linecap="round")",
            d.s, st.color, n1(lw));
        if (!st.dash.empty()) o.f(R"( stroke-dasharray="{}")", st.dash);
        o.s += "/>\n";
      }
      // Isolated points (a one-point series, or a point between gaps) get a small dot.
      Out dots;
      for (const auto& seg : segs)
        if (seg.size() == 1 && !st.markers)
          append_marker(dots, seg.front(), 0, std::max(2.4, 1.4 * lw));
      if (!dots.s.empty())
        o.f(R"(<path class="dots" d="{}" fill="{}" stroke="none"/>)"
            "\n",
            dots.s, st.color);
    }
    if (st.markers) {
      Out d;
      for (const Pt& q : marker_points(s, m))
        append_marker(d, q, st.shape, kMarkerRadius);
      if (!d.s.empty())
        o.f(R"(<path class="markers" d="{}" fill="none" stroke="{}" stroke-width="1.2"/>)"
            "\n",
            d.s, st.color);
    }
  }
  o.s += "</g>\n";

  draw_legend(o, entries, L, plot.right() + kLegendGap, plot.y);
  o.s += "</g>\n";
}

} // namespace

// -----------------------------------------------------------------------------------------------
// Public functions

TimeAxis choose_time_axis(double t_max_seconds) {
  if (!(t_max_seconds > 600)) return {"s", 1.0}; // also NaN and negative
  if (t_max_seconds <= 7200) return {"min", 60.0};
  return {"h", 3600.0};
}

Ticks nice_ticks(double lo, double hi, int max_ticks) {
  return make_ticks(lo, hi, max_ticks, StepSet::decimal);
}

std::vector<std::string> tick_labels(const Ticks& ticks) {
  std::vector<std::string> out;
  double max_abs = 0;
  for (const double v : ticks.values)
    max_abs = std::max(max_abs, std::fabs(v));
  const bool exp_mode = max_abs >= 1e6 || (max_abs > 0 && max_abs < 1e-3);
  const double step = ticks.step > 0 && std::isfinite(ticks.step) ? ticks.step : 1.0;
  const int step_exp = static_cast<int>(std::floor(std::log10(step) + 1e-9));
  for (const double v : ticks.values) {
    if (!std::isfinite(v)) {
      out.push_back(format_number(v));
    } else if (std::fabs(v) < step * 1e-6) {
      out.push_back("0");
    } else if (exp_mode) {
      const int ve = static_cast<int>(std::floor(std::log10(std::fabs(v)) + 1e-12));
      out.push_back(exponent_form(v, std::max(0, ve - step_exp)));
    } else {
      out.push_back(fixed_form(v, std::max(0, -step_exp)));
    }
  }
  return out;
}

std::string format_number(double value, int digits) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  if (value == 0) return "0";
  digits = std::clamp(digits, 1, 17);
  const double a = std::fabs(value);
  if (a >= 1e6 || a < 1e-3) return exponent_form(value, digits - 1);
  const int mag = static_cast<int>(std::floor(std::log10(a)));
  const std::string s = fixed_form(value, std::max(0, digits - 1 - mag));
  // Rounding may carry into a new digit (999999.7 -> "1000000"): switch to exponent form.
  return std::fabs(std::stod(s)) >= 1e6 ? exponent_form(value, digits - 1) : s;
}

std::string xml_escape(std::string_view text) {
  std::string out;
  append_escaped(out, sanitize(text));
  return out;
}

int palette_size() {
  return static_cast<int>(kPalette.size());
}

std::string palette_color(int index) {
  const int n = palette_size();
  return kPalette[static_cast<std::size_t>(((index % n) + n) % n)];
}

std::string render_svg(const Figure& fig) {
  const double width = std::clamp(fig.width, 240, 20000);
  const double panel_h = std::clamp(fig.panel_height, 160, 20000);
  const int n = static_cast<int>(fig.panels.size());
  const int cols = std::clamp(fig.columns, 1, std::max(1, n));
  const int rows = (n + cols - 1) / cols;
  const std::string title = sanitize(fig.title);
  const double title_h = title.empty() ? 0 : kFigureTitleFont + 18;
  const double height = std::max(title_h + rows * panel_h, 60.0);

  Out o;
  o.s.reserve(64 * 1024);
  o.s += "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n";
  o.f(R"(<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{0}" height="{1}" )"
      R"(viewBox="0 0 {0} {1}" font-family="{2}" font-size="12">)"
      "\n",
      n1(width), n1(height), kFontFamily);
  if (!title.empty()) {
    o.s += "<title>";
    o.text(title);
    o.s += "</title>\n";
  }
  o.f(R"(<rect x="0" y="0" width="{}" height="{}" fill="#ffffff"/>)"
      "\n",
      n1(width), n1(height));
  if (!title.empty()) {
    o.f(R"(<text x="{}" y="{}" text-anchor="middle" font-size="{}" font-weight="bold" fill="#111111">)",
        n1(width / 2), n1(8 + kFigureTitleFont), n1(kFigureTitleFont));
    o.text(fit_text(title, width - 16, kFigureTitleFont, true));
    o.s += "</text>\n";
  }
  const double cell_w = width / cols;
  for (int i = 0; i < n; ++i) {
    const Rect cell{(i % cols) * cell_w, title_h + (i / cols) * panel_h, cell_w, panel_h};
    render_panel(o, fig.panels[static_cast<std::size_t>(i)], i, cell);
  }
  o.s += "</svg>\n";
  return o.s;
}

void write_svg(const Figure& fig, const std::string& path) {
  const std::string svg = render_svg(fig);
  std::ofstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("cannot write plot file '" + path + "'");
  f.write(svg.data(), static_cast<std::streamsize>(svg.size()));
  if (!f) throw std::runtime_error("cannot write plot file '" + path + "'");
}

} // namespace thermnet::plot
