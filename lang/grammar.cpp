#include "lang/grammar.hpp"

#include "lang/grammar_x3.hpp"

namespace thermnet::lang::grammar {

namespace x3 = boost::spirit::x3;

template <typename Rule, typename Attr> bool Grammar::run(It& p, const Rule& rule, Attr& attr) {
  builder_.reset();
  try {
    return x3::phrase_parse(p, builder_.end, x3::with<x3_rules::builder_tag>(builder_)[rule],
                            x3_rules::line_space, attr, x3::skip_flag::dont_post_skip);
  } catch (const x3::expectation_failure<It>& e) {
    throw Expected{e.where(), e.which()};
  }
}

It Grammar::skip(It p) const {
  x3::parse(p, builder_.end, -x3_rules::line_space);
  return p;
}

bool Grammar::at_word(It p, std::string_view word) const {
  return static_cast<std::size_t>(builder_.end - p) >= word.size() &&
         std::string_view(p, word.size()) == word &&
         (p + word.size() == builder_.end || !is_ident_char(p[word.size()]));
}

bool Grammar::statement(It& p, ast::Statement& out, Place place) {
  builder_.param_value_optional = place == Place::submodel;
  return run(p, x3_rules::statement, out);
}

bool Grammar::case_header(It& p, ast::Identifier& name) {
  return run(p, x3_rules::case_header, name);
}

bool Grammar::case_item(It& p, ast::CaseItem& out) {
  return run(p, x3_rules::case_item, out);
}

bool Grammar::loop_header(It& p, std::vector<ast::LoopRange>& ranges) {
  return run(p, x3_rules::loop_header, ranges);
}

bool Grammar::submodel_header(It& p, ast::SubmodelStmt& out) {
  if (run(p, x3_rules::submodel_header, out)) return true;
  out.name = {};
  out.terminals.clear();
  return false;
}

bool Grammar::expr(It& p, ast::Expr& out) {
  ast::Index root = ast::none;
  if (!run(p, x3_rules::expression, root)) return false;
  out = builder_.expr(root);
  return true;
}

} // namespace thermnet::lang::grammar
