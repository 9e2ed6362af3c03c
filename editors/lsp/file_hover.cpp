#include "editors/lsp/file_hover.hpp"

#include "lang/display_text.hpp"

#include <fmt/format.h>

#include <variant>

namespace thermnet::lsp {
namespace {

namespace ast = lang::ast;

/// Text written in the model, as inline code (escaped: it may hold anything).
std::string code(std::string_view s) {
  std::string t = lang::escape_for_display(s);
  return t.find('`') == std::string::npos ? fmt::format("`{}`", t) : fmt::format("`` {} ``", t);
}

/// The syntax tree of the file with id `file`, or nullptr when the model has none.
const ast::File* file_of(const lang::Model& m, lang::FileId file) {
  for (const auto& f : m.files())
    if (f->file_id == file) return f.get();
  return nullptr;
}

/// The lines that say how a file's time column and fields are read.
std::string layout_lines(const ast::FileOptions& o) {
  std::string out;
  if (o.time)
    out += fmt::format("- time: column {}{}\n", code(o.time->column.text),
                       o.time->unit
                           ? fmt::format(" [{}]", lang::escape_for_display(o.time->unit->text))
                           : " (seconds)");
  else
    out += "- time: the first column, `time`, in seconds\n";
  out += fmt::format("- separator: {}\n", o.separator ? code(o.separator->text) : "`,`");
  return out;
}

/// The data statements of the cases, in order, with their case's name.
std::vector<std::pair<std::string, const ast::CaseData*>> case_data(const lang::Model& m) {
  std::vector<std::pair<std::string, const ast::CaseData*>> out;
  for (const auto& c : m.cases())
    for (const auto& item : c.stmt->items)
      if (const auto* d = std::get_if<ast::CaseData>(&item)) out.emplace_back(c.name, d);
  return out;
}

/// The source text of a span of `text` (empty when out of range).
std::string_view slice(std::string_view text, const ast::Tagged& t) {
  if (t.begin > t.end || t.end > text.size()) return {};
  return text.substr(t.begin, t.end - t.begin);
}

} // namespace

std::optional<SpanText> table_hover(const lang::Model& m, lang::FileId file, std::size_t at) {
  const ast::File* f = file_of(m, file);
  if (!f) return std::nullopt;
  const ast::TableSignal* table = nullptr;
  for (const auto& s : f->signals)
    if (const auto* t = std::get_if<ast::TableSignal>(&s))
      if (t->begin <= at && at < t->end &&
          (!table || t->end - t->begin < table->end - table->begin))
        table = t;
  if (!table) return std::nullopt;
  std::string md;
  if (table->case_data) {
    md = fmt::format("**table** — column {} of the case's data file, as a signal\n\n",
                     code(table->column.text));
  } else {
    md = fmt::format("**table** — column {} of {}, as a signal\n\n", code(table->column.text),
                     code(table->file.text));
  }
  md += table->hold ? "- held (`hold`): each row's value holds until the next row; the solver "
                      "restarts only where the value changes\n"
                    : "- linear between rows (add `hold` for a switch or a set point)\n";
  if (!table->case_data) md += layout_lines(table->options);
  md += table->unit
            ? fmt::format("- unit: [{}]\n", lang::escape_for_display(table->unit->text))
            : "- unit: none written (bare numbers: the expression around gives their unit)\n";
  if (table->case_data) {
    const auto data = case_data(m);
    if (data.empty()) {
      md += "\nNo case has a data file: outside a case the table is 0.\n";
    } else {
      md += "\nRead from each case's data file, in the layout its data statement gives:\n\n";
      for (const auto& [name, d] : data)
        md += fmt::format("- case {}: {}\n", code(name), code(d->path.text));
    }
  }
  return SpanText{std::move(md), table->begin, table->end};
}

std::optional<SpanText> data_statement_hover(const lang::Model& m, lang::FileId file,
                                             std::size_t at, std::string_view text) {
  for (const auto& c : m.cases()) {
    if (c.file != file) continue;
    for (const auto& item : c.stmt->items) {
      const auto* d = std::get_if<ast::CaseData>(&item);
      if (!d || at < d->begin || at >= d->end) continue;
      for (const auto& map : d->columns)
        if (map.target.begin <= at && at <= map.target.end) return std::nullopt;
      std::string md = fmt::format("**data** — measured data of case {}: {}\n\n", code(c.name),
                                   code(d->path.text));
      md += layout_lines(d->options);
      md += fmt::format("- temperatures in {}\n",
                        d->unit ? fmt::format("[{}]", lang::escape_for_display(d->unit->text))
                                : "degC (unless a series gives its unit)");
      if (!d->mapped) {
        md += "\nEvery column other than the time is compared with the node, boundary or sensor "
              "of its name.\n";
      } else {
        md += "\nCompared (the other columns are not: they may be inputs read with "
              "`table(data, \"COLUMN\")`):\n\n";
        for (const auto& map : d->columns) {
          std::string from;
          for (const auto& s : map.sources)
            from += fmt::format("{}{}", from.empty() ? "" : ", ", code(slice(text, s)));
          md += fmt::format(
              "- {} with {}{}{}\n", code(slice(text, map.target)),
              map.mean ? "the mean of " : "column ", from,
              map.unit ? fmt::format(" [{}]", lang::escape_for_display(map.unit->text)) : "");
        }
      }
      return SpanText{std::move(md), d->begin, d->end};
    }
  }
  return std::nullopt;
}

} // namespace thermnet::lsp
