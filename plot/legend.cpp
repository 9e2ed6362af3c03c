#include "plot/legend.hpp"

#include "plot/text.hpp"

#include <algorithm>
#include <cmath>

namespace thermnet::plot {
namespace {

constexpr double kSwatchWidth = 26;  // swatch plus gap before the text
constexpr double kLegendColGap = 12; // between legend columns

// The swatch of one entry, 20 px wide from x, centred on y_mid.
void draw_swatch(SvgWriter& o, const LegendEntry& e, double x, double y_mid) {
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

} // namespace

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

void draw_legend(SvgWriter& o, const std::vector<LegendEntry>& entries, const LegendLayout& L,
                 double x0, double y0) {
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

} // namespace thermnet::plot
