#include "plot/style.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace thermnet::plot {
namespace {

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

} // namespace

int palette_size() {
  return static_cast<int>(kPalette.size());
}

std::string palette_color(int index) {
  const int n = palette_size();
  return kPalette[static_cast<std::size_t>(((index % n) + n) % n)];
}

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

double line_width_of(const Series& s) {
  return std::isfinite(s.line_width) ? std::clamp(s.line_width, 0.5, 4.0) : 1.5;
}

} // namespace thermnet::plot
