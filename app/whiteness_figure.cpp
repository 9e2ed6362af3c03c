#include "app/whiteness_figure.hpp"

#include <fmt/format.h>

namespace thermnet::app {

plot::Figure whiteness_figure(const std::vector<SeriesWhiteness>& tests, const std::string& title) {
  plot::Figure fig;
  fig.title = title;
  fig.columns = 2;
  fig.panel_height = 320;
  for (const auto& s : tests) {
    const Whiteness& w = s.test;
    const std::string where = fmt::format("{}, case {}", s.node, s.case_name);
    plot::Panel acf;
    acf.title = fmt::format("{}: autocorrelation ({})", where, w.acf_white ? "white" : "not white");
    acf.x_label = "lag [h]";
    acf.y_label = "ACF";
    plot::Series values, hi, lo;
    values.label = "ACF";
    values.style = plot::LineStyle::markers_line;
    values.color = 0;
    hi.label = "±1.96/√n";
    hi.style = lo.style = plot::LineStyle::dashed;
    hi.color = lo.color = 1;
    for (std::size_t k = 0; k < w.acf.size(); ++k) {
      const double lag_h = static_cast<double>(k) * w.dt / 3600.0;
      values.x.push_back(lag_h);
      values.y.push_back(w.acf[k]);
    }
    if (!values.x.empty()) {
      hi.x = lo.x = {values.x.front(), values.x.back()};
      hi.y = {w.acf_bound, w.acf_bound};
      lo.y = {-w.acf_bound, -w.acf_bound};
    }
    acf.series = {values, hi, lo};
    acf.y_range = std::make_pair(-1.0, 1.0);
    plot::Panel cp;
    cp.title = fmt::format("{}: cumulated periodogram ({})", where,
                           w.cpgram_white ? "white" : "not white");
    cp.x_label = "frequency [1/h]";
    cp.y_label = "cumulated periodogram";
    plot::Series cum, upper, lower;
    cum.label = "cumulated";
    cum.color = 0;
    upper.label = "Kolmogorov-Smirnov 95 %";
    upper.style = lower.style = plot::LineStyle::dashed;
    upper.color = lower.color = 1;
    for (std::size_t k = 0; k < w.frequency.size(); ++k) {
      cum.x.push_back(w.frequency[k] * 3600.0);
      cum.y.push_back(w.cumulated[k]);
    }
    if (!cum.x.empty()) {
      const double fmax = 0.5 / w.dt * 3600.0, c = w.ks_bound;
      upper.x = {0.0, fmax * (1 - c)};
      upper.y = {c, 1.0};
      lower.x = {fmax * c, fmax};
      lower.y = {0.0, 1 - c};
    }
    cp.series = {cum, upper, lower};
    cp.y_range = std::make_pair(0.0, 1.0);
    fig.panels.push_back(std::move(acf));
    fig.panels.push_back(std::move(cp));
  }
  return fig;
}

} // namespace thermnet::app
