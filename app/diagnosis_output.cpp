// What a diagnosis writes beside its report: the extended model, the lines of each finding and
// the before/after figure.

#include "app/diagnosis_output.hpp"

#include "app/output_files.hpp"
#include "lang/path_policy.hpp"
#include "lang/rewrite/case_blocks.hpp"
#include "lang/rewrite/param_values.hpp"
#include "lang/units.hpp"
#include "plot/style.hpp"
#include "plot/svg_plot.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>

namespace thermnet::app {
namespace {

using lang::kZeroCelsius;

/// Palette indices of the plot's worst nodes, in rank order: the first ones as far apart as the
/// palette allows (blue, vermillion, black, orange), so no two nodes of a panel look alike.
constexpr std::array<int, 8> kNodeColors = {0, 1, 6, 4, 3, 5, 2, 7};

} // namespace

std::string finding_comment(const Finding& f) {
  return fmt::format(
      "# thermnet diagnose: {} [{}]{} -- {}\n# RMSE {:.4g} -> {:.4g} K (held-out {:.4g} -> "
      "{:.4g} K)\n",
      f.candidate.kind, fmt::join(f.candidate.nodes, ", "),
      f.candidate.mechanism.empty() ? "" : " (" + f.candidate.mechanism + ")", f.evidence,
      f.rmse_before, f.rmse_after, f.validation_rmse_before, f.validation_rmse_after);
}

std::string finding_lines(const Finding& f) {
  std::string s = finding_comment(f);
  for (const auto& name : f.retired)
    s += fmt::format("# (the declaration of {} is commented out: the lines below replace it)\n",
                     name);
  if (!f.param_rewrites.empty()) {
    s += "# (the declared values of the ranged params are rewritten:)\n";
    for (const auto& [name, value] : f.param_rewrites)
      s += fmt::format("#   {} = {} (SI)\n", name, netlist_number(value));
  } else if (!f.statement.empty()) {
    s += f.statement + "\n";
  }
  for (const auto& [name, lines] : f.case_statements)
    s += fmt::format("# inside case {} {{ ... }}:\n{}\n", name, lines);
  return s;
}

std::vector<rewrite::RewrittenFile> extended_model_files(const lang::Model& model, const Finding& f,
                                                         const std::string& out) {
  const long root = model.sources().find(model.path());
  if (root < 0) throw OutputError("the model's own text is no longer available");
  const auto file = static_cast<lang::FileId>(root);
  const std::string why = finding_comment(f);
  // The ranged params it recalibrated are rewritten where they are declared (an included file
  // is written as a rewritten copy beside the output, as calibrate -o does).
  std::vector<rewrite::ParamUpdate> updates;
  std::string applied;
  if (!f.param_rewrites.empty()) {
    for (const auto& p : model.params())
      if (auto it = f.param_rewrites.find(p.name); it != f.param_rewrites.end())
        updates.push_back({p, it->second});
    applied = "# (the declared values of the ranged params were rewritten)\n";
  } else {
    applied = f.statement.empty() ? "" : f.statement + "\n";
  }
  std::vector<std::string> elsewhere;
  auto edits = rewrite::case_block_edits(model, file, f.case_statements,
                                         "# thermnet diagnose: " + f.candidate.kind, elsewhere);
  if (!edits.empty()) applied += "# (with the lines marked in the case blocks above)\n";
  // The declarations the finding's statements replace are kept as comments.
  const std::string& text = model.sources().text(file);
  for (const auto& name : f.retired)
    for (const auto& d : model.elements())
      if (d.name == name && d.file == file && !d.scope) {
        const lang::Span where = d.where();
        std::string old = text.substr(where.begin, where.end - where.begin), commented = "# ";
        for (char ch : old)
          commented += ch == '\n' ? std::string("\n# ") : std::string(1, ch);
        edits.push_back({where.begin, where.end,
                         commented + "  # replaced by thermnet diagnose: " + f.candidate.kind});
      }
  for (const auto& name : elsewhere) {
    applied +=
        fmt::format("# not applied: case {} is not in this file; add inside its block:\n", name);
    std::string lines = f.case_statements.at(name);
    for (auto p = lines.find('\n'); p != std::string::npos; p = lines.find('\n', p + 5))
      lines.replace(p, 1, "\n#   ");
    applied += "#   " + lines + "\n";
  }
  auto files = rewrite::rewrite_model(model.sources(), file, updates, out, std::move(edits));
  std::string& written = files.front().text;
  if (!written.empty() && written.back() != '\n') written += '\n';
  written += "\n" + why + applied;
  return files;
}

std::string extended_model_text(const lang::Model& model, const Finding& f) {
  return extended_model_files(model, f, model.path() + ".extended.tnet").front().text;
}

std::string diagnosis_svg(const DiagnosisReport& r, const std::string& model_name,
                          std::size_t worst) {
  const std::string title = r.findings.empty() ? fmt::format("{} — no finding", model_name)
                                               : fmt::format("{} — before and after {}", model_name,
                                                             r.findings.front().candidate.kind);
  return plot::render_svg(diagnosis_figure(r, title, worst, true));
}

plot::Figure diagnosis_figure(const DiagnosisReport& r, const std::string& title, std::size_t worst,
                              bool with_after, std::size_t from, std::size_t to) {
  std::vector<std::pair<std::string, double>> nodes;
  for (const auto& [name, m] : r.baseline.nodes)
    nodes.emplace_back(name, m.rmse);
  std::stable_sort(nodes.begin(), nodes.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  // One colour per node: never more nodes than distinct colours.
  worst = std::min({worst, kNodeColors.size(), static_cast<std::size_t>(plot::palette_size())});
  if (nodes.size() > worst) nodes.resize(worst);
  plot::Figure fig;
  fig.title = title;
  for (const auto& cv : r.curves) {
    // The curves before and after: the declared model and the best finding's, or two steps.
    const auto* before = &cv.before;
    const auto* after = &cv.after;
    if (to >= 1 && to <= cv.steps.size()) {
      after = &cv.steps[to - 1];
      if (from >= 1 && from <= cv.steps.size()) before = &cv.steps[from - 1];
    }
    plot::Panel panel;
    panel.title = "case " + cv.case_name + " (worst nodes)";
    panel.x_label = "time";
    panel.y_label = "temperature [°C]";
    panel.x_is_time_s = true;
    for (std::size_t rank = 0; rank < nodes.size(); ++rank) {
      const std::string& name = nodes[rank].first;
      auto add = [&](const std::map<std::string, std::vector<double>>& m, const std::string& label,
                     plot::LineStyle style) {
        auto it = m.find(name);
        if (it == m.end() || it->second.empty()) return;
        plot::Series s;
        s.label = name + " " + label;
        s.style = style;
        s.color = kNodeColors[rank];
        s.x = cv.times;
        for (double v : it->second)
          s.y.push_back(v - kZeroCelsius);
        panel.series.push_back(std::move(s));
      };
      add(cv.measured, "measured", plot::LineStyle::markers);
      add(*before, with_after ? "before" : "simulated", plot::LineStyle::solid);
      if (with_after) add(*after, "after", plot::LineStyle::dashed);
    }
    fig.panels.push_back(std::move(panel));
  }
  return fig;
}

} // namespace thermnet::app
