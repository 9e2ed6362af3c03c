#include "plot/panel.hpp"

#include "plot/axis.hpp"
#include "plot/geometry.hpp"
#include "plot/legend.hpp"
#include "plot/style.hpp"
#include "plot/text.hpp"
#include "plot/ticks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace thermnet::plot {
namespace {

constexpr double kTickFont = 11;
constexpr double kLabelFont = 12;
constexpr double kPanelTitleFont = 13;

// The displayed unit of the x axis: for time in seconds, the unit chosen from the largest time
// shown (the label gets it too); otherwise the data's own.
struct XUnit {
  double divisor = 1;               // data units per displayed unit
  StepSet steps = StepSet::decimal; // tick steps of that unit
  std::string label;                // sanitised
};

XUnit x_unit(const Panel& p) {
  XUnit u;
  u.label = sanitize(p.x_label);
  if (!p.x_is_time_s) return u;
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
  u.divisor = ta.divisor;
  u.steps = ta.unit == "h"     ? StepSet::hours
            : ta.unit == "min" ? StepSet::minutes
                               : StepSet::decimal;
  u.label = u.label.empty() ? fmt::format("time [{}]", ta.unit)
                            : fmt::format("{} [{}]", u.label, ta.unit);
  return u;
}

// The range to show (x in the displayed unit): the data's, or a default one without data.
struct DataRange {
  double xlo = std::numeric_limits<double>::infinity(), xhi = -xlo;
  double ylo = xlo, yhi = -xlo;
  bool has_data = false; // something can be drawn
};

// The range of what can be drawn, skipping non-finite points and, on log axes, non-positive ones.
DataRange data_range(const Panel& p, double divisor) {
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
  r.has_data = r.xlo <= r.xhi;
  if (!r.has_data) {
    r.xlo = p.log_x ? 1 : 0;
    r.xhi = p.log_x ? 10 : 1;
    r.ylo = p.log_y ? 1 : 0;
    r.yhi = p.log_y ? 10 : 1;
  }
  return r;
}

// How the series and bands are drawn, and the legend's entries.
struct PanelStyles {
  std::vector<Style> series;       // one per series
  std::vector<std::string> bands;  // colour of each band
  std::vector<LegendEntry> legend; // labelled series, then labelled bands
};

PanelStyles panel_styles(const Panel& p) {
  PanelStyles st;
  int auto_series = 0, auto_band = 0;
  for (const auto& s : p.series) {
    const int ci = s.color >= 0 ? s.color : auto_series++;
    st.series.push_back(series_style(s, ci));
    if (!s.label.empty())
      st.legend.push_back({sanitize(s.label), st.series.back(), line_width_of(s), false});
  }
  for (const auto& b : p.bands) {
    const int ci = b.color >= 0 ? b.color : auto_band++;
    st.bands.push_back(palette_color(ci));
    if (!b.label.empty()) {
      LegendEntry e;
      e.label = sanitize(b.label);
      e.style.color = st.bands.back();
      e.band = true;
      st.legend.push_back(std::move(e));
    }
  }
  return st;
}

// Where everything goes in the panel's cell.
struct PanelLayout {
  std::string title;         // sanitised
  std::string x_label;       // sanitised, with the time unit
  std::string y_label;       // sanitised
  double title_baseline = 0; // y of the title's baseline
  Rect plot{};               // the plot area
  Axis xa, ya;               // axes, pixels set
  LegendLayout legend;       // the legend, right of the plot area
};

// The x axis with as many ticks as fit without their labels crowding.
Axis x_axis(const Panel& p, const DataRange& r, const XUnit& xu, Rect plot) {
  Axis xa;
  for (int mt = std::clamp(static_cast<int>(plot.w / 45), 2, 12);; --mt) {
    xa = make_axis(p.log_x, r.xlo, r.xhi, p.x_range, xu.divisor, Fit::snap, mt, xu.steps);
    xa.p0 = plot.x;
    xa.p1 = plot.right();
    if (mt <= 2 || min_tick_gap(xa) >= max_label_width(xa, kTickFont) + 10) return xa;
  }
}

// Title on top, x labels below, the y axis's labels setting the left margin and the legend the
// right one.
PanelLayout layout_panel(const Panel& p, Rect cell, const XUnit& xu, const DataRange& r,
                         const std::vector<LegendEntry>& entries) {
  PanelLayout L;
  L.title = sanitize(p.title);
  L.x_label = xu.label;
  L.y_label = sanitize(p.y_label);
  double top = cell.y + 8;
  L.title_baseline = top + kPanelTitleFont;
  if (!L.title.empty()) top += kPanelTitleFont + 8;
  const double plot_top = top + 8;
  const double plot_bottom =
      cell.bottom() - 8 - (L.x_label.empty() ? 0 : kLabelFont + 8) - kTickFont - 8;
  const double plot_h = std::max(40.0, plot_bottom - plot_top);

  L.ya = make_axis(p.log_y, r.ylo, r.yhi, p.y_range, 1.0, Fit::extend,
                   std::clamp(static_cast<int>(plot_h / 40), 2, 10), StepSet::decimal);
  const double left =
      8 + (L.y_label.empty() ? 0 : kLabelFont + 8) + max_label_width(L.ya, kTickFont) + 8;
  L.legend = layout_legend(entries, plot_h, std::min(0.42 * cell.w, std::max(0.3 * cell.w, 260.0)));
  const double right = entries.empty() ? 24 : 10 + L.legend.width;
  L.plot = Rect{cell.x + left, plot_top, std::max(40.0, cell.w - left - right), plot_h};
  L.ya.p0 = L.plot.bottom();
  L.ya.p1 = L.plot.y;
  L.xa = x_axis(p, r, xu, L.plot);
  // Minor grid lines of log axes only where decades are wide enough to show them clearly.
  if (std::fabs(L.xa.pixel_t(1) - L.xa.pixel_t(0)) < 80) L.xa.minor.clear();
  if (std::fabs(L.ya.pixel_t(1) - L.ya.pixel_t(0)) < 80) L.ya.minor.clear();
  return L;
}

// The clip path of the data: the plot area with room for markers on its edges.
void draw_clip_path(SvgWriter& o, const std::string& clip_id, Rect plot) {
  o.f(R"(<clipPath id="{}"><rect x="{}" y="{}" width="{}" height="{}"/></clipPath>)", clip_id,
      n1(plot.x - kMarkerRadius - 1), n1(plot.y - kMarkerRadius - 1),
      n1(plot.w + 2 * kMarkerRadius + 2), n1(plot.h + 2 * kMarkerRadius + 2));
  o.s += '\n';
}

// Grid lines at transformed positions xs (vertical) and ys (horizontal), inside the frame.
void draw_grid_lines(SvgWriter& o, const PanelLayout& L, const std::vector<double>& xs,
                     const std::vector<double>& ys, const char* color) {
  const Rect& plot = L.plot;
  SvgWriter d;
  for (const double t : xs) {
    const double px = std::round(L.xa.pixel_t(t)) + 0.5;
    if (px <= plot.x + 1 || px >= plot.right() - 1) continue;
    d.s += 'M';
    d.num(px);
    d.s += ' ';
    d.num(plot.y);
    d.s += 'V';
    d.num(plot.bottom());
  }
  for (const double t : ys) {
    const double py = std::round(L.ya.pixel_t(t)) + 0.5;
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
}

// Grid: minor (log axes), major, then a zero line.
void draw_grid(SvgWriter& o, const PanelLayout& L) {
  draw_grid_lines(o, L, L.xa.minor, L.ya.minor, "#eeeeee");
  draw_grid_lines(o, L, L.xa.major, L.ya.major, "#dcdcdc");
  if (!L.ya.log && L.ya.lo < 0 && L.ya.hi > 0) draw_grid_lines(o, L, {}, {0.0}, "#a8a8a8");
}

// The frame of the plot area and the tick marks outside it.
void draw_frame(SvgWriter& o, const PanelLayout& L) {
  const Rect& plot = L.plot;
  o.f(R"(<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#8c8c8c" stroke-width="1"/>)"
      "\n",
      n1(plot.x), n1(plot.y), n1(plot.w), n1(plot.h));
  SvgWriter d;
  for (const double t : L.xa.major) {
    d.s += 'M';
    d.num(L.xa.pixel_t(t));
    d.s += ' ';
    d.num(plot.bottom());
    d.s += "v4";
  }
  for (const double t : L.ya.major) {
    d.s += 'M';
    d.num(plot.x);
    d.s += ' ';
    d.num(L.ya.pixel_t(t));
    d.s += "h-4";
  }
  if (!d.s.empty())
    o.f(R"(<path d="{}" fill="none" stroke="#8c8c8c" stroke-width="1"/>)"
        "\n",
        d.s);
}

// The labels of the ticks: below the x axis, left of the y axis.
void draw_tick_labels(SvgWriter& o, const PanelLayout& L) {
  o.f(R"(<g font-size="{}" fill="#333333">)", n1(kTickFont));
  for (std::size_t i = 0; i < L.xa.major.size(); ++i) {
    o.f(R"(<text x="{}" y="{}" text-anchor="middle">)", n1(L.xa.pixel_t(L.xa.major[i])),
        n1(L.plot.bottom() + 6 + kTickFont));
    o.text(L.xa.labels[i]);
    o.s += "</text>";
  }
  for (std::size_t i = 0; i < L.ya.major.size(); ++i) {
    o.f(R"(<text x="{}" y="{}" text-anchor="end">)", n1(L.plot.x - 7),
        n1(L.ya.pixel_t(L.ya.major[i]) + kTickFont * 0.35));
    o.text(L.ya.labels[i]);
    o.s += "</text>";
  }
  o.s += "</g>\n";
}

// The axis labels and the panel's title.
void draw_titles(SvgWriter& o, const PanelLayout& L, Rect cell) {
  const Rect& plot = L.plot;
  if (!L.x_label.empty()) {
    o.f(R"(<text x="{}" y="{}" text-anchor="middle" font-size="{}" fill="#222222">)",
        n1(plot.x + plot.w / 2), n1(plot.bottom() + 6 + kTickFont + 8 + kLabelFont),
        n1(kLabelFont));
    o.text(fit_text(L.x_label, plot.w, kLabelFont));
    o.s += "</text>\n";
  }
  if (!L.y_label.empty()) {
    const double x = cell.x + 8 + kLabelFont;
    const double y = plot.y + plot.h / 2;
    o.f(R"~(<text x="{0}" y="{1}" transform="rotate(-90 {0} {1})" text-anchor="middle" font-size="{2}" )~"
        R"(fill="#222222">)",
        n1(x), n1(y), n1(kLabelFont));
    o.text(fit_text(L.y_label, plot.h, kLabelFont));
    o.s += "</text>\n";
  }
  if (!L.title.empty()) {
    // Centred over the plot area when it fits there, else shifted (and cut) to stay in the cell.
    const std::string shown = fit_text(L.title, cell.w - 16, kPanelTitleFont, true);
    const double half = 0.55 * text_width(shown, kPanelTitleFont);
    const double cx = std::clamp(plot.x + plot.w / 2, cell.x + 8 + half,
                                 std::max(cell.x + 8 + half, cell.right() - 8 - half));
    o.f(R"(<text x="{}" y="{}" text-anchor="middle" font-size="{}" font-weight="bold" fill="#111111">)",
        n1(cx), n1(L.title_baseline), n1(kPanelTitleFont));
    o.text(shown);
    o.s += "</text>\n";
  }
}

// "no data" in the middle of an empty plot area.
void draw_no_data(SvgWriter& o, Rect plot) {
  o.f(R"(<text x="{}" y="{}" text-anchor="middle" font-size="{}" fill="#999999">no data</text>)"
      "\n",
      n1(plot.x + plot.w / 2), n1(plot.y + plot.h / 2), n1(kLabelFont));
}

// One band: its outline filled.
void draw_band(SvgWriter& o, const Band& b, const std::string& color, const Mapping& m) {
  const auto polys = band_polygons(b, m);
  if (polys.empty()) return;
  SvgWriter d;
  append_polygons(d, polys);
  o.f(R"(<path class="band" d="{}" fill="{}" fill-opacity="0.2" stroke="{}" stroke-opacity="0.45" )"
      R"(stroke-width="0.8" stroke-linejoin="round"/>)"
      "\n",
      d.s, color, color);
}

// One series: its line (with a dot on each isolated point) and its markers, as its style says.
void draw_series(SvgWriter& o, const Series& s, const Style& st, const Mapping& m) {
  const double lw = line_width_of(s);
  if (st.line) {
    const auto segs = line_segments(s, m);
    SvgWriter d;
    append_polylines(d, segs);
    if (!d.s.empty()) {
      o.f(R"(<path class="series" d="{}" fill="none" stroke="{}" stroke-width="{}" )"
          R"(stroke-linejoin="round" stroke-linecap="round")",
          d.s, st.color, n1(lw));
      if (!st.dash.empty()) o.f(R"( stroke-dasharray="{}")", st.dash);
      o.s += "/>\n";
    }
    // Isolated points (a one-point series, or a point between gaps) get a small dot.
    SvgWriter dots;
    for (const auto& seg : segs)
      if (seg.size() == 1 && !st.markers)
        append_marker(dots, seg.front(), 0, std::max(2.4, 1.4 * lw));
    if (!dots.s.empty())
      o.f(R"(<path class="dots" d="{}" fill="{}" stroke="none"/>)"
          "\n",
          dots.s, st.color);
  }
  if (st.markers) {
    SvgWriter d;
    for (const Point& q : marker_points(s, m))
      append_marker(d, q, st.shape, kMarkerRadius);
    if (!d.s.empty())
      o.f(R"(<path class="markers" d="{}" fill="none" stroke="{}" stroke-width="1.2"/>)"
          "\n",
          d.s, st.color);
  }
}

// Bands, then series, clipped to the plot area.
void draw_data(SvgWriter& o, const Panel& p, const PanelStyles& styles, const Mapping& m,
               const std::string& clip_id) {
  o.f(R"~(<g clip-path="url(#{})">)~"
      "\n",
      clip_id);
  for (std::size_t k = 0; k < p.bands.size(); ++k)
    draw_band(o, p.bands[k], styles.bands[k], m);
  for (std::size_t k = 0; k < p.series.size(); ++k)
    draw_series(o, p.series[k], styles.series[k], m);
  o.s += "</g>\n";
}

} // namespace

void render_panel(SvgWriter& o, const Panel& p, const std::string& clip_id, Rect cell) {
  const XUnit xu = x_unit(p);
  const DataRange r = data_range(p, xu.divisor);
  const PanelStyles styles = panel_styles(p);
  const PanelLayout L = layout_panel(p, cell, xu, r, styles.legend);
  o.f("<g class=\"panel\">\n");
  draw_clip_path(o, clip_id, L.plot);
  draw_grid(o, L);
  draw_frame(o, L);
  draw_tick_labels(o, L);
  draw_titles(o, L, cell);
  if (!r.has_data) draw_no_data(o, L.plot);
  draw_data(o, p, styles, Mapping{&L.xa, &L.ya, xu.divisor, L.plot}, clip_id);
  draw_legend(o, styles.legend, L.legend, L.plot.right() + kLegendGap, L.plot.y);
  o.s += "</g>\n";
}

} // namespace thermnet::plot
