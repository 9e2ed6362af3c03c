#include "plot/style.hpp"
#include "plot/svg_plot.hpp"
#include "plot/text.hpp"
#include "plot/ticks.hpp"

#include <doctest/doctest.h>
#include <fmt/format.h>

#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

using namespace thermnet::plot;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

bool is_name_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == ':' ||
         c == '.';
}

// Checks an entity reference starting at s[i] == '&'; advances i past it.
bool valid_entity(const std::string& s, std::size_t& i) {
  const std::size_t semi = s.find(';', i);
  if (semi == std::string::npos || semi - i > 10) return false;
  const std::string name = s.substr(i + 1, semi - i - 1);
  i = semi + 1;
  if (name == "amp" || name == "lt" || name == "gt" || name == "quot" || name == "apos")
    return true;
  if (name.size() >= 2 && name[0] == '#') {
    const bool hex = name[1] == 'x';
    const std::string digits = name.substr(hex ? 2 : 1);
    if (digits.empty()) return false;
    for (const char c : digits)
      if (!(hex ? std::isxdigit(static_cast<unsigned char>(c))
                : std::isdigit(static_cast<unsigned char>(c))))
        return false;
    return true;
  }
  return false;
}

// A small XML 1.0 well-formedness checker: returns "" or a description of the first problem.
std::string xml_error(const std::string& s) {
  // Characters: valid UTF-8, no control characters other than tab, newline, carriage return.
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x20 && c != '\t' && c != '\n' && c != '\r') return "control character";
    std::size_t len = c < 0x80             ? 1
                      : (c & 0xE0) == 0xC0 ? 2
                      : (c & 0xF0) == 0xE0 ? 3
                      : (c & 0xF8) == 0xF0 ? 4
                                           : 0;
    if (len == 0 || i + len > s.size()) return "bad UTF-8";
    for (std::size_t k = 1; k < len; ++k)
      if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return "bad UTF-8";
    i += len;
  }
  std::vector<std::string> open;
  bool seen_root = false;
  std::size_t i = 0;
  if (s.rfind("<?xml", 0) != 0) return "no XML declaration";
  while (i < s.size()) {
    if (s[i] != '<') {
      if (s[i] == '&') {
        if (!valid_entity(s, i)) return "bad entity in text";
        continue;
      }
      if (open.empty() && !std::isspace(static_cast<unsigned char>(s[i])))
        return "text outside root";
      ++i;
      continue;
    }
    if (s.compare(i, 4, "<!--") == 0) {
      const std::size_t e = s.find("-->", i + 4);
      if (e == std::string::npos) return "unterminated comment";
      i = e + 3;
      continue;
    }
    if (s.compare(i, 2, "<?") == 0) {
      const std::size_t e = s.find("?>", i + 2);
      if (e == std::string::npos) return "unterminated processing instruction";
      i = e + 2;
      continue;
    }
    if (s.compare(i, 2, "</") == 0) {
      std::size_t j = i + 2;
      while (j < s.size() && is_name_char(s[j]))
        ++j;
      const std::string name = s.substr(i + 2, j - i - 2);
      while (j < s.size() && std::isspace(static_cast<unsigned char>(s[j])))
        ++j;
      if (j >= s.size() || s[j] != '>') return "bad end tag " + name;
      if (open.empty() || open.back() != name) return "mismatched end tag " + name;
      open.pop_back();
      i = j + 1;
      continue;
    }
    // Start tag.
    std::size_t j = i + 1;
    while (j < s.size() && is_name_char(s[j]))
      ++j;
    const std::string name = s.substr(i + 1, j - i - 1);
    if (name.empty()) return "empty tag name";
    if (open.empty()) {
      if (seen_root) return "second root element";
      seen_root = true;
    }
    std::set<std::string> attrs;
    for (;;) {
      const std::size_t ws = j;
      while (j < s.size() && std::isspace(static_cast<unsigned char>(s[j])))
        ++j;
      if (j >= s.size()) return "unterminated tag " + name;
      if (s[j] == '>') {
        open.push_back(name);
        ++j;
        break;
      }
      if (s.compare(j, 2, "/>") == 0) {
        j += 2;
        break;
      }
      if (ws == j) return "missing space before attribute in " + name;
      const std::size_t a = j;
      while (j < s.size() && is_name_char(s[j]))
        ++j;
      const std::string attr = s.substr(a, j - a);
      if (attr.empty() || j >= s.size() || s[j] != '=') return "bad attribute in " + name;
      if (!attrs.insert(attr).second) return "duplicate attribute " + attr;
      ++j;
      if (j >= s.size() || (s[j] != '"' && s[j] != '\'')) return "unquoted attribute " + attr;
      const char q = s[j++];
      while (j < s.size() && s[j] != q) {
        if (s[j] == '<') return "'<' in attribute " + attr;
        if (s[j] == '&') {
          if (!valid_entity(s, j)) return "bad entity in attribute " + attr;
          continue;
        }
        ++j;
      }
      if (j >= s.size()) return "unterminated attribute " + attr;
      ++j;
    }
    i = j;
  }
  if (!open.empty()) return "unclosed element " + open.back();
  if (!seen_root) return "no root element";
  return "";
}

// Values of attribute `attr` of every element whose start tag contains `marker`.
std::vector<std::string> attributes(const std::string& svg, const std::string& marker,
                                    const std::string& attr) {
  std::vector<std::string> out;
  for (std::size_t pos = svg.find(marker); pos != std::string::npos;
       pos = svg.find(marker, pos + 1)) {
    const std::size_t start = svg.rfind('<', pos);
    const std::size_t end = svg.find('>', pos);
    const std::string tag = svg.substr(start, end - start);
    const std::size_t a = tag.find(" " + attr + "=\"");
    if (a == std::string::npos) {
      out.emplace_back();
      continue;
    }
    const std::size_t v = a + attr.size() + 3;
    out.push_back(tag.substr(v, tag.find('"', v) - v));
  }
  return out;
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + what.size()))
    ++n;
  return n;
}

// Subpaths (M commands) and coordinate pairs of a path made of M/L and implicit line-tos.
struct PathStats {
  std::size_t subpaths = 0;
  std::vector<std::pair<double, double>> points;
};

PathStats path_stats(const std::string& d) {
  PathStats st;
  std::vector<double> nums;
  const char* p = d.c_str();
  while (*p) {
    if (*p == 'M') ++st.subpaths;
    if (*p == '-' || *p == '.' || std::isdigit(static_cast<unsigned char>(*p))) {
      char* end = nullptr;
      nums.push_back(std::strtod(p, &end));
      p = end;
    } else {
      ++p;
    }
  }
  for (std::size_t k = 0; k + 1 < nums.size(); k += 2)
    st.points.push_back({nums[k], nums[k + 1]});
  return st;
}

Series make_series(std::string label, std::vector<double> x, std::vector<double> y) {
  Series s;
  s.label = std::move(label);
  s.x = std::move(x);
  s.y = std::move(y);
  return s;
}

Figure one_panel(Panel p) {
  Figure f;
  f.panels.push_back(std::move(p));
  return f;
}

std::vector<std::string> labels_of(double lo, double hi, int max_ticks = 8) {
  return tick_labels(nice_ticks(lo, hi, max_ticks));
}

} // namespace

TEST_CASE("svg_plot: the XML checker itself rejects broken documents") {
  const std::string head = "<?xml version=\"1.0\"?>\n";
  CHECK(xml_error(head + "<svg><g></g></svg>").empty());
  CHECK_FALSE(xml_error(head + "<svg><g></svg>").empty());
  CHECK_FALSE(xml_error(head + "<svg><text>a < b</text></svg>").empty());
  CHECK_FALSE(xml_error(head + "<svg><text>a & b</text></svg>").empty());
  CHECK_FALSE(xml_error(head + "<svg a=\"x\" a=\"y\"/>").empty());
  CHECK_FALSE(xml_error(head + "<svg a=\"x\"\"/>").empty());
  CHECK_FALSE(xml_error(head + "<svg/><svg/>").empty());
}

TEST_CASE("svg_plot: nice ticks") {
  SUBCASE("0..97") {
    const Ticks t = nice_ticks(0, 97, 8);
    CHECK(t.values == std::vector<double>{0, 20, 40, 60, 80, 100});
    CHECK(t.step == 20);
  }
  SUBCASE("-38.5..22") {
    const Ticks t = nice_ticks(-38.5, 22, 8);
    CHECK(t.values == std::vector<double>{-40, -30, -20, -10, 0, 10, 20, 30});
    CHECK(labels_of(-38.5, 22) ==
          std::vector<std::string>{"-40", "-30", "-20", "-10", "0", "10", "20", "30"});
  }
  SUBCASE("fractional steps are exact decimals") {
    const Ticks t = nice_ticks(0, 1, 6);
    CHECK(t.values == std::vector<double>{0, 0.2, 0.4, 0.6, 0.8, 1.0});
    CHECK(labels_of(0.1, 0.7, 7) ==
          std::vector<std::string>{"0.1", "0.2", "0.3", "0.4", "0.5", "0.6", "0.7"});
    CHECK(nice_ticks(0.1, 0.7, 7).values[2] == 0.3);
  }
  SUBCASE("every range gives at most max_ticks 1-2-5 ticks covering it") {
    const std::vector<std::pair<double, double>> ranges = {
        {0, 1},       {-1e-7, 3e-7}, {293.15, 293.16}, {1e6, 3.7e9},
        {-5, -4.999}, {0.001, 1000}, {-1e5, 1},        {17, 17.0001}};
    for (const auto& range : ranges) {
      const double lo = range.first, hi = range.second;
      for (int mt = 2; mt <= 12; ++mt) {
        const Ticks t = nice_ticks(lo, hi, mt);
        CAPTURE(lo);
        CAPTURE(hi);
        CAPTURE(mt);
        REQUIRE(t.values.size() >= 2);
        CHECK(static_cast<int>(t.values.size()) <= std::max(mt, 3));
        if (mt >= 3) CHECK(static_cast<int>(t.values.size()) <= mt);
        CHECK(t.values.front() <= lo);
        CHECK(t.values.back() >= hi);
        const double mant = t.step / std::pow(10.0, std::floor(std::log10(t.step) + 1e-9));
        CHECK((std::fabs(mant - 1) < 1e-9 || std::fabs(mant - 2) < 1e-9 ||
               std::fabs(mant - 5) < 1e-9));
        for (std::size_t k = 1; k < t.values.size(); ++k)
          CHECK(t.values[k] - t.values[k - 1] == doctest::Approx(t.step).epsilon(1e-9));
      }
    }
  }
  SUBCASE("degenerate ranges are padded") {
    const Ticks flat = nice_ticks(20, 20, 8);
    CHECK(flat.values.front() < 20);
    CHECK(flat.values.back() > 20);
    const Ticks zero = nice_ticks(0, 0, 8);
    CHECK(zero.values.front() <= -1);
    CHECK(zero.values.back() >= 1);
    const Ticks reversed = nice_ticks(10, 0, 8);
    CHECK(reversed.values.front() == 0);
    CHECK(reversed.values.back() == 10);
    CHECK(nice_ticks(kNaN, kInf, 5).values.size() >= 2);
    CHECK(nice_ticks(-1, 3, 2).values == std::vector<double>{-5, 0, 5});
    CHECK(nice_ticks(1, 3, 2).values == std::vector<double>{0, 5});
  }
}

TEST_CASE("svg_plot: label formatting") {
  CHECK(format_number(0.1 + 0.2) == "0.3");
  CHECK(format_number(1234.5678) == "1234.57");
  CHECK(format_number(20.0) == "20");
  CHECK(format_number(-0.0) == "0");
  CHECK(format_number(-2.5) == "-2.5");
  CHECK(format_number(1e-7) == "1e-7");
  CHECK(format_number(2.5e9) == "2.5e9");
  CHECK(format_number(999999.7) == "1e6");
  CHECK(format_number(0.00125) == "0.00125");
  CHECK(format_number(kNaN) == "nan");
  CHECK(format_number(-kInf) == "-inf");

  CHECK(tick_labels({{0, 0.5, 1, 1.5}, 0.5}) == std::vector<std::string>{"0", "0.5", "1", "1.5"});
  CHECK(tick_labels({{0, 5e5, 1e6, 1.5e6}, 5e5}) ==
        std::vector<std::string>{"0", "5e5", "1e6", "1.5e6"});
  CHECK(tick_labels({{0, 2e-5, 4e-5}, 2e-5}) == std::vector<std::string>{"0", "2e-5", "4e-5"});
  CHECK(tick_labels({{1000, 2000, 3000}, 1000}) ==
        std::vector<std::string>{"1000", "2000", "3000"});
  CHECK(tick_labels({{0.1 + 0.2}, 0.1}) == std::vector<std::string>{"0.3"});
  // A tick at zero computed with round-off still reads "0".
  CHECK(tick_labels({{-0.1, 0.1 + 0.2 - 0.3, 0.1}, 0.1}) ==
        std::vector<std::string>{"-0.1", "0", "0.1"});
}

TEST_CASE("svg_plot: time axis choice") {
  CHECK(choose_time_axis(0).unit == "s");
  CHECK(choose_time_axis(500).unit == "s");
  CHECK(choose_time_axis(600).unit == "s");
  CHECK(choose_time_axis(601).unit == "min");
  CHECK(choose_time_axis(7200).unit == "min");
  CHECK(choose_time_axis(7200).divisor == 60);
  CHECK(choose_time_axis(7201).unit == "h");
  CHECK(choose_time_axis(3 * 3600).divisor == 3600);
  CHECK(choose_time_axis(kNaN).unit == "s");
  CHECK(choose_time_axis(-5).unit == "s");

  Panel p;
  p.x_is_time_s = true;
  Series s = make_series("T", {}, {});
  for (int i = 0; i <= 1080; ++i) {
    s.x.push_back(i * 10.0);
    s.y.push_back(20 + std::sin(i / 100.0));
  }
  p.series.push_back(s);
  const std::string svg = render_svg(one_panel(p));
  CHECK(svg.find(">time [h]</text>") != std::string::npos);
  // x tick labels in hours: 0 .. 3.
  CHECK(svg.find(">3</text>") != std::string::npos);
  CHECK(svg.find(">10800</text>") == std::string::npos);

  p.x_label = "elapsed";
  for (double& x : p.series[0].x)
    x /= 100; // 0 .. 108 s
  const std::string svg_s = render_svg(one_panel(p));
  CHECK(svg_s.find(">elapsed [s]</text>") != std::string::npos);
}

TEST_CASE("svg_plot: escaping") {
  CHECK(xml_escape("a<b & \"c\" 'd' >") == "a&lt;b &amp; &quot;c&quot; &apos;d&apos; &gt;");
  CHECK(xml_escape("T [\xC2\xB0"
                   "C]") == "T [\xC2\xB0"
                            "C]"); // valid UTF-8 kept
  CHECK(xml_escape(std::string("a\x01"
                               "b\nc",
                               5)) == "a b c"); // control characters become spaces
  CHECK(xml_escape("bad \xFF byte") == "bad \xEF\xBF\xBD byte");
  CHECK(xml_escape("cut \xE2\x82") == "cut \xEF\xBF\xBD\xEF\xBF\xBD");

  Figure f;
  f.title = "<script>alert('x')</script> & co";
  Panel p;
  p.title = "a \"quoted\" <title>";
  p.x_label = "x & y";
  p.y_label = "T <K>";
  p.series.push_back(make_series("<b>node</b> & \"friends\"", {0, 1}, {1, 2}));
  p.bands.push_back(Band{"band <&>", {0, 1}, {0, 1}, {2, 3}, -1});
  f.panels.push_back(p);
  const std::string svg = render_svg(f);
  CHECK(xml_error(svg).empty());
  CHECK(svg.find("<script>") == std::string::npos);
  CHECK(svg.find("&lt;script&gt;alert(&apos;x&apos;)&lt;/script&gt; &amp; co") !=
        std::string::npos);
  CHECK(svg.find("&lt;b&gt;node&lt;/b&gt; &amp; &quot;friends&quot;") != std::string::npos);
  CHECK(svg.find("x &amp; y") != std::string::npos);
}

TEST_CASE("svg_plot: document structure and determinism") {
  Panel p;
  p.title = "T";
  p.series.push_back(make_series("a", {0, 1, 2}, {3, 1, 2}));
  const Figure f = one_panel(p);
  const std::string svg = render_svg(f);
  CHECK(xml_error(svg).empty());
  CHECK(svg.rfind("<?xml version=\"1.0\" encoding=\"UTF-8\"", 0) == 0);
  CHECK(svg.find("xmlns=\"http://www.w3.org/2000/svg\"") != std::string::npos);
  CHECK(svg.find("version=\"1.1\"") != std::string::npos);
  CHECK(svg.find("viewBox=\"0 0 960 420\"") != std::string::npos);
  CHECK(svg.find("fill=\"#ffffff\"") != std::string::npos);
  CHECK(svg.find("sans-serif") != std::string::npos);
  CHECK(svg == render_svg(f));
}

TEST_CASE("svg_plot: edge cases give well-formed SVG without nan or inf") {
  std::vector<Figure> figs;
  figs.push_back(Figure{}); // no panels at all
  {
    Figure f;
    f.title = "empty panels";
    f.columns = 3;
    f.panels.resize(4);
    f.panels[1].log_y = true;
    f.panels[2].x_is_time_s = true;
    figs.push_back(f);
  }
  {
    Panel p;
    p.series.push_back(make_series("empty", {}, {}));
    p.series.push_back(make_series("one point", {5}, {7}));
    p.series.push_back(make_series("flat", {0, 1, 2}, {20, 20, 20}));
    p.series.push_back(make_series("zero-width x", {3, 3, 3}, {1, 2, 3}));
    p.series.push_back(make_series("mismatched sizes", {0, 1, 2, 3}, {1, 2}));
    p.series.push_back(make_series("all missing", {0, 1}, {kNaN, kNaN}));
    p.series.push_back(make_series("huge values", {0, 1, 2, kInf}, {kInf, 1, -kInf, 2}));
    p.bands.push_back(Band{"band with gaps", {0, 1, 2, 3}, {0, kNaN, 1, 1}, {1, 2, 2, kInf}, -1});
    figs.push_back(one_panel(p));
  }
  {
    Panel p;
    p.series.push_back(make_series("only point", {1e9}, {-1e-9}));
    figs.push_back(one_panel(p));
  }
  {
    Panel p; // all values equal, including x
    p.series.push_back(make_series("same", {2, 2}, {0, 0}));
    figs.push_back(one_panel(p));
  }
  {
    Panel p; // log axes with non-positive and tiny values
    p.log_x = true;
    p.log_y = true;
    p.series.push_back(
        make_series("errs", {-1, 0, 1e-12, 1e-3, 1, 10}, {1, -2, 1e-300, 1e-5, 0.1, 0}));
    p.series.back().style = LineStyle::markers_line;
    figs.push_back(one_panel(p));
  }
  {
    Panel p; // fixed ranges, some data far outside, huge magnitudes
    p.x_range = std::make_pair(0.0, 10.0);
    p.y_range = std::make_pair(-1.0, 1.0);
    p.series.push_back(make_series("wild", {-1e300, 0, 5, 1e300}, {1e300, 0.5, -1e300, 0}));
    p.series.push_back(make_series("markers", {-5, 1, 2, 50}, {0, 1e200, 0.5, 0}));
    p.series.back().style = LineStyle::markers;
    figs.push_back(one_panel(p));
  }
  {
    Panel p; // bogus ranges and styles
    p.x_range = std::make_pair(kNaN, 1.0);
    p.y_range = std::make_pair(5.0, 5.0);
    p.log_y = true;
    p.series.push_back(make_series("s", {0, 1}, {1, 2}));
    p.series.back().color = 12345;
    p.series.back().line_width = -3;
    p.series.push_back(make_series("t", {0, 1}, {2, 1}));
    p.series.back().line_width = kNaN;
    Figure f = one_panel(p);
    f.width = -10;
    f.panel_height = 0;
    f.columns = -2;
    figs.push_back(f);
  }
  for (std::size_t k = 0; k < figs.size(); ++k) {
    CAPTURE(k);
    const std::string svg = render_svg(figs[k]);
    CHECK(xml_error(svg) == "");
    CHECK(svg.find("nan") == std::string::npos);
    CHECK(svg.find("inf") == std::string::npos);
    CHECK(svg.find("e+") == std::string::npos); // no exponents in coordinates
  }
}

TEST_CASE("svg_plot: NaN and infinity break the line") {
  Panel p;
  p.series.push_back(make_series("gap", {0, 1, 2, 3, 4, 5}, {1, 2, kNaN, 3, 4, 5}));
  p.series.push_back(make_series("inf gap", {0, 1, 2, 3, 4, 5}, {1, 2, 3, kInf, 4, 5}));
  p.series.push_back(make_series("no gap", {0, 1, 2, 3, 4, 5}, {1, 2, 3, 3, 4, 5}));
  const std::string svg = render_svg(one_panel(p));
  REQUIRE(xml_error(svg).empty());
  const auto ds = attributes(svg, "class=\"series\"", "d");
  REQUIRE(ds.size() == 3);
  CHECK(path_stats(ds[0]).subpaths == 2);
  CHECK(path_stats(ds[1]).subpaths == 2);
  CHECK(path_stats(ds[2]).subpaths == 1);

  // An isolated point between gaps is drawn as a dot, not lost.
  Panel q;
  q.series.push_back(make_series("island", {0, 1, 2, 3, 4}, {1, kNaN, 2, kNaN, 3}));
  const std::string svg2 = render_svg(one_panel(q));
  const auto dots = attributes(svg2, "class=\"dots\"", "d");
  REQUIRE(dots.size() == 1);
  CHECK(path_stats(dots[0]).subpaths == 3);
}

TEST_CASE("svg_plot: decimation bounds huge series and keeps peaks") {
  const std::size_t n = 1000000;
  Series s;
  s.label = "";
  s.x.resize(n);
  s.y.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    s.x[i] = static_cast<double>(i);
    s.y[i] = 50 + 10 * std::sin(static_cast<double>(i) * 0.37); // noisy band 40..60
  }
  s.y[500001] = 100;  // one-sample spike
  s.y[700003] = kNaN; // sub-pixel gap
  Panel p;
  p.y_range = std::make_pair(0.0, 100.0);
  p.series.push_back(s);
  const std::string svg = render_svg(one_panel(p));
  CHECK(xml_error(svg).empty());
  CHECK(svg.size() < 200 * 1024);
  const auto ds = attributes(svg, "class=\"series\"", "d");
  REQUIRE(ds.size() == 1);
  const PathStats st = path_stats(ds[0]);
  CHECK(st.points.size() <= 4 * 960);
  CHECK(st.points.size() > 100);
  // The spike reaches the top of the plot area (the frame's y).
  const auto frame_y = attributes(svg, "stroke=\"#8c8c8c\" stroke-width=\"1\"/>", "y");
  REQUIRE_FALSE(frame_y.empty());
  double min_y = 1e9;
  for (const auto& pt : st.points)
    min_y = std::min(min_y, pt.second);
  CHECK(min_y == doctest::Approx(std::stod(frame_y[0])).epsilon(1e-3));

  // Non-increasing x (a parametric curve) is still bounded.
  Series loop;
  for (std::size_t i = 0; i < n; ++i) {
    loop.x.push_back(std::cos(static_cast<double>(i) * 0.001));
    loop.y.push_back(std::sin(static_cast<double>(i) * 0.0013));
  }
  Panel q;
  q.series.push_back(loop);
  const std::string svg2 = render_svg(one_panel(q));
  CHECK(xml_error(svg2).empty());
  CHECK(svg2.size() < 300 * 1024);

  // Dense markers are thinned to about one per marker-sized cell.
  Series dense = s;
  dense.style = LineStyle::markers;
  Panel r;
  r.series.push_back(dense);
  const std::string svg3 = render_svg(one_panel(r));
  CHECK(xml_error(svg3).empty());
  CHECK(svg3.size() < 300 * 1024);
}

TEST_CASE("svg_plot: legend entries") {
  Panel p;
  p.series.push_back(make_series("a", {0, 1}, {0, 1}));
  p.series.push_back(make_series("", {0, 1}, {1, 0})); // unlabelled: not in the legend
  p.series.push_back(make_series("c", {0, 1}, {1, 1}));
  p.series.back().style = LineStyle::markers;
  p.bands.push_back(Band{"band", {0, 1}, {0, 0}, {1, 1}, -1});
  const std::string svg = render_svg(one_panel(p));
  CHECK(count(svg, "class=\"legend-entry\"") == 3);

  // Many series: all listed (wrapped into columns or smaller text), or summarised with "+N more".
  for (const int n : {24, 60, 300}) {
    CAPTURE(n);
    Panel q;
    for (int k = 0; k < n; ++k)
      q.series.push_back(make_series("node_" + std::to_string(k), {0, 1}, {0, 1.0 * k}));
    const std::string s2 = render_svg(one_panel(q));
    CHECK(xml_error(s2).empty());
    const std::size_t entries = count(s2, "class=\"legend-entry\"");
    if (n <= 60) {
      CHECK(entries == static_cast<std::size_t>(n));
    } else {
      CHECK(entries < static_cast<std::size_t>(n));
      CHECK(s2.find("+" + std::to_string(n - entries) + " more") != std::string::npos);
    }
    // The legend sits to the right of the plot area: every legend text starts right of the frame.
    const auto fx = attributes(s2, "stroke=\"#8c8c8c\" stroke-width=\"1\"/>", "x");
    const auto fw = attributes(s2, "stroke=\"#8c8c8c\" stroke-width=\"1\"/>", "width");
    const double plot_right = std::stod(fx[0]) + std::stod(fw[0]);
    const std::size_t legend = s2.find("class=\"legend\"");
    for (const auto& x : attributes(s2.substr(legend), "<text", "x"))
      CHECK(std::stod(x) > plot_right);
  }
}

TEST_CASE("svg_plot: palette and dash cycling keep 20+ series distinguishable") {
  CHECK(palette_size() >= 8);
  CHECK(palette_color(0) != palette_color(1));
  CHECK(palette_color(palette_size()) == palette_color(0));
  CHECK(palette_color(-1) == palette_color(palette_size() - 1));
  Panel p;
  for (int k = 0; k < 30; ++k)
    p.series.push_back(make_series(fmt::format("s{}", k), {0, 1}, {0, 1.0 * k}));
  const std::string svg = render_svg(one_panel(p));
  const auto strokes = attributes(svg, "class=\"series\"", "stroke");
  const auto dashes = attributes(svg, "class=\"series\"", "stroke-dasharray");
  REQUIRE(strokes.size() == 30);
  std::set<std::pair<std::string, std::string>> styles;
  for (std::size_t k = 0; k < strokes.size(); ++k)
    styles.insert({strokes[k], dashes[k]});
  CHECK(styles.size() == 30);

  // Explicit colours: a measured/simulated pair shares one colour.
  Panel q;
  q.series.push_back(make_series("measured", {0, 1}, {0, 1}));
  q.series.back().style = LineStyle::markers;
  q.series.back().color = 2;
  q.series.push_back(make_series("simulated", {0, 1}, {0, 1}));
  q.series.back().color = 2;
  const std::string svg2 = render_svg(one_panel(q));
  CHECK(attributes(svg2, "class=\"markers\"", "stroke") ==
        std::vector<std::string>{palette_color(2)});
  CHECK(attributes(svg2, "class=\"series\"", "stroke") ==
        std::vector<std::string>{palette_color(2)});
}

TEST_CASE("svg_plot: log axes label decades") {
  Panel p;
  p.log_y = true;
  p.series.push_back(make_series("err", {1, 2, 3, 4}, {1e-4, 1e-3, 0.05, 2}));
  const std::string svg = render_svg(one_panel(p));
  CHECK(xml_error(svg).empty());
  for (const char* label :
       {">1e-4</text>", ">0.001</text>", ">0.01</text>", ">0.1</text>", ">1</text>", ">10</text>"})
    CHECK(svg.find(label) != std::string::npos);
}

TEST_CASE("svg_plot: multi-panel layout") {
  Figure f;
  f.title = "diagnose";
  f.columns = 2;
  f.panel_height = 300;
  for (int k = 0; k < 3; ++k) {
    Panel p;
    p.title = "panel " + std::to_string(k);
    p.series.push_back(make_series("before", {0, 1}, {0, 1}));
    p.series.push_back(make_series("after", {0, 1}, {1, 0}));
    p.series.back().style = LineStyle::dashed;
    f.panels.push_back(p);
  }
  const std::string svg = render_svg(f);
  CHECK(xml_error(svg).empty());
  CHECK(count(svg, "class=\"panel\"") == 3);
  CHECK(svg.find("viewBox=\"0 0 960 634\"") != std::string::npos); // 34 px title + 2 rows of 300
  CHECK(count(svg, "clip-path=\"url(#clip") == 3);
  CHECK(count(svg, "stroke-dasharray=\"6 4\"") >= 3);
}
