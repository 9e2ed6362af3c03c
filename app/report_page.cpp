#include "app/report_page.hpp"

#include "app/command_line.hpp"
#include "app/whiteness_figure.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace thermnet::app {

std::string page_number(double v, int digits) {
  if (!std::isfinite(v)) return "—";
  return fmt::format("{:.{}g}", v, digits);
}

void add_run_facts(plot::HtmlPage& page, const std::string& model,
                   const std::vector<NamedInput>& inputs,
                   const std::vector<std::pair<std::string, std::string>>& more) {
  std::vector<std::pair<std::string, std::string>> facts = {
      {"model", model},
      {"command", command_line()},
      {"thermnet", std::string("version ") + THERMNET_VERSION},
      {"date", report_date()}};
  facts.insert(facts.end(), more.begin(), more.end());
  page.facts(facts);
  plot::HtmlTable files;
  files.caption = "Files read";
  files.head = {"file", "what it is"};
  for (const auto& in : inputs)
    files.rows.push_back({in.path, in.role});
  if (!files.rows.empty()) page.table(files);
}

CaseInnovations simulated_series(const std::string& case_name, const std::vector<double>& times,
                                 const std::vector<std::string>& nodes,
                                 const std::vector<std::vector<double>>& measured,
                                 const std::vector<std::vector<double>>& simulated) {
  CaseInnovations c;
  c.case_name = case_name;
  c.times = times;
  c.nodes = nodes;
  c.measured = measured;
  c.predicted = simulated;
  return c;
}

void add_whiteness(plot::HtmlPage& page, const std::vector<SeriesWhiteness>& tests,
                   const std::string& what, const std::string& name, std::size_t most) {
  plot::HtmlTable t;
  t.caption = "Whiteness tests of the " + what + ", every series";
  t.head = {"node",
            "case",
            "points",
            "RMS [K]",
            "ACF: lags outside ±1.96/√n",
            "ACF: most allowed",
            "largest |ACF| at lag [s]",
            "cumulated periodogram: largest deviation",
            "its 95 % bound",
            "white"};
  t.align = {plot::Align::left,  plot::Align::left,  plot::Align::right, plot::Align::right,
             plot::Align::right, plot::Align::right, plot::Align::right, plot::Align::right,
             plot::Align::right, plot::Align::left};
  for (const auto& s : tests) {
    const Whiteness& w = s.test;
    t.rows.push_back({s.node, s.case_name, std::to_string(w.n), page_number(s.innovation_rms),
                      std::to_string(w.acf_outside), std::to_string(w.acf_allowed),
                      page_number(static_cast<double>(w.acf_peak_lag) * w.dt),
                      page_number(w.ks_max, 3), page_number(w.ks_bound, 3),
                      w.white()        ? "yes"
                      : w.acf_white    ? "no (periodogram)"
                      : w.cpgram_white ? "no (autocorrelation)"
                                       : "no (both tests)"});
  }
  page.table(t);
  // The figure: the series with the largest errors (the table lists every one).
  std::vector<std::size_t> order(tests.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return tests[a].innovation_rms > tests[b].innovation_rms;
  });
  if (order.size() > most) order.resize(most);
  std::vector<SeriesWhiteness> shown;
  for (const std::size_t k : order)
    if (tests[k].test.n > 0) shown.push_back(tests[k]);
  if (shown.empty()) return;
  const std::string which = shown.size() == tests.size()
                                ? std::string("every series")
                                : fmt::format("the {} series with the largest RMS error of {}",
                                              shown.size(), tests.size());
  page.figure(whiteness_figure(shown, ""),
              fmt::format("Autocorrelation of the {0} against the lag, with the ±1.96/√n band "
                          "of white noise (dashed), and their cumulated periodogram against the "
                          "frequency, with the 95 % Kolmogorov-Smirnov band around the diagonal "
                          "of white noise (dashed); {1}.",
                          what, which),
              name);
}

} // namespace thermnet::app
