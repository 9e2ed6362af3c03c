// Unit tests of `calibrate -o` across files: which files are rewritten and where they go, include
// and data paths in the copies, the user's inputs never overwritten, the written model loading
// with the new values, units kept in expressions, and outputs written all-or-nothing.

#include "app/output_files.hpp"
#include "kernel/core/element_registry.hpp"
#include "lang/rewrite/model_files.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "loaded_model.hpp"
#include "temp_dir.hpp"

using thermnet::test::TempDir;

namespace {

namespace fs = std::filesystem;
using namespace thermnet;

/// A loaded model and its root file.
struct Loaded : test::LoadedModel {
  using LoadedModel::LoadedModel;
  /// The model's own file (not an included one).
  lang::FileId root() const {
    const long id = sources.find(model->path());
    REQUIRE(id >= 0);
    return static_cast<lang::FileId>(id);
  }
};

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// main.tnet includes lib/mid.tnet (no param), which includes lib/params.tnet (the ranged
/// params), and geometry.tnet (nothing to change); one case reads heat.csv.
struct Tree {
  TempDir dir{"rewrite"};
  Tree() {
    dir.write("heat.csv", "time,a\n0,20\n60,21\n");
    dir.write("geometry.tnet", "# geometry\nnode a C = Ca\nboundary amb T = 20\n");
    dir.write("lib/params.tnet", "# unknowns\n"
                                 "param G  = 3 [W/K]  range 0.5 .. 5   # conductance a-amb\n"
                                 "param Ca = 0.5 [kJ/K] range 0.1 [kJ/K] .. 2 [kJ/K] \"cap\"\n");
    dir.write("lib/mid.tnet", "# middle\ninclude \"params.tnet\"  # the unknowns\n");
    dir.write("main.tnet", "model m  # root\n"
                           "include \"lib/mid.tnet\"\n"
                           "include \"geometry.tnet\"\n"
                           "param h = 5 range 1 .. 10\n"
                           "conductance g a amb G = G * h / 5\n"
                           "case heat { duration = 60; data \"heat.csv\" }\n");
  }
  std::string path(const std::string& name) const { return (dir.path / name).string(); }
};

std::vector<rewrite::ParamUpdate> updates_for(const lang::Model& m) {
  std::vector<rewrite::ParamUpdate> u;
  for (const auto& p : m.params())
    u.push_back({p, p.name == "G" ? 2.25 : p.name == "Ca" ? 1250.0 : 7.5});
  return u;
}

} // namespace

TEST_CASE("rewrite_model: the files declaring params and their includers, beside OUT") {
  Tree t;
  Loaded m(t.path("main.tnet"));
  fs::create_directories(t.dir.path / "out");
  auto files =
      rewrite::rewrite_model(m.sources, m.root(), updates_for(*m.model), t.path("out/cal.tnet"));
  REQUIRE(files.size() == 3);
  CHECK(files[0].path == t.path("out/cal.tnet"));
  CHECK(files[0].text == "model m  # root\n"
                         "include \"cal.mid.tnet\"\n"
                         "include \"../geometry.tnet\"\n"
                         "param h = 7.5 range 1 .. 10\n"
                         "conductance g a amb G = G * h / 5\n"
                         "case heat { duration = 60; data \"../heat.csv\" }\n");
  CHECK(files[1].path == t.path("out/cal.mid.tnet"));
  CHECK(files[1].text == "# middle\ninclude \"cal.params.tnet\"  # the unknowns\n");
  CHECK(files[2].path == t.path("out/cal.params.tnet"));
  CHECK(m.sources.path(files[2].source) == t.path("lib/params.tnet"));
  CHECK(files[2].text == "# unknowns\n"
                         "param G  = 2.25 [W/K]  range 0.5 .. 5   # conductance a-amb\n"
                         "param Ca = 1.25 [kJ/K] range 0.1 [kJ/K] .. 2 [kJ/K] \"cap\"\n");

  SUBCASE("written, the model loads clean and declares the new values") {
    std::vector<app::OutputFile> out;
    for (const auto& f : files)
      out.push_back({f.path, f.text});
    app::write_output_files(out);
    Loaded back(t.path("out/cal.tnet"));
    back.model->lint(back.diags);
    CHECK(back.diags.error_count() == 0);
    std::map<std::string, double> values;
    for (const auto& p : back.model->params())
      values[p.name] = p.value;
    CHECK(values.at("G") == doctest::Approx(2.25));
    CHECK(values.at("Ca") == doctest::Approx(1250.0));
    CHECK(values.at("h") == doctest::Approx(7.5));
    CHECK(read(t.dir.path / "lib/params.tnet").find("param G  = 3 [W/K]") != std::string::npos);
  }
}

TEST_CASE(
    "rewrite_model: only the root when every param is declared there; same folder keeps paths") {
  Tree t;
  Loaded m(t.path("main.tnet"));
  std::vector<rewrite::ParamUpdate> only_h;
  for (const auto& u : updates_for(*m.model))
    if (u.param.name == "h") only_h.push_back(u);
  auto files = rewrite::rewrite_model(m.sources, m.root(), only_h, t.path("cal.tnet"));
  REQUIRE(files.size() == 1);
  CHECK(files[0].text == rewrite::apply_edits(m.sources.text(m.root()),
                                              rewrite::param_edits(m.sources, m.root(), only_h)));
  CHECK(files[0].text.find("include \"lib/mid.tnet\"") != std::string::npos);
  CHECK(files[0].text.find("data \"heat.csv\"") != std::string::npos);
}

TEST_CASE("rewrite_model: the user's inputs are never targets, the model itself included") {
  Tree t;
  Loaded m(t.path("main.tnet"));
  const auto updates = updates_for(*m.model);
  CHECK_THROWS_AS(rewrite::rewrite_model(m.sources, m.root(), updates, t.path("lib/params.tnet")),
                  rewrite::RewriteError);
  CHECK_THROWS_AS(rewrite::rewrite_model(m.sources, m.root(), updates, t.path("heat.csv")),
                  rewrite::RewriteError);
  CHECK_THROWS_AS(rewrite::rewrite_model(m.sources, m.root(), updates, t.path("main.tnet")),
                  rewrite::RewriteError);
  // Through a symlink, the model is still the model.
  fs::create_symlink(t.path("main.tnet"), t.path("link.tnet"));
  CHECK_THROWS_AS(rewrite::rewrite_model(m.sources, m.root(), updates, t.path("link.tnet")),
                  rewrite::RewriteError);
  // A copy's name that an input already has gets a number.
  t.dir.write("cal.mid.tnet", "# an input that happens to have the copy's name\n");
  t.dir.write("main.tnet", read(t.dir.path / "main.tnet") + "include \"cal.mid.tnet\"\n");
  Loaded m2(t.path("main.tnet"));
  auto files =
      rewrite::rewrite_model(m2.sources, m2.root(), updates_for(*m2.model), t.path("cal.tnet"));
  REQUIRE(files.size() == 3);
  CHECK(files[1].path == t.path("cal.mid-2.tnet"));
  CHECK(files[0].text.find("include \"cal.mid-2.tnet\"") != std::string::npos);
  CHECK(files[0].text.find("include \"cal.mid.tnet\"") != std::string::npos);
}

TEST_CASE("rewrite_model: a copy never goes through a symlink (issue 51)") {
  Tree t;
  Loaded m(t.path("main.tnet"));
  const auto updates = updates_for(*m.model);
  // A symlink planted at the copy's name, leading out of the folder: skipped, not written through.
  t.dir.write("elsewhere/victim.txt", "victim\n");
  fs::create_symlink(t.path("elsewhere/victim.txt"), t.path("cal.mid.tnet"));
  fs::create_symlink(t.path("nowhere/dangling.tnet"), t.path("cal.params.tnet"));
  auto files = rewrite::rewrite_model(m.sources, m.root(), updates, t.path("cal.tnet"));
  REQUIRE(files.size() == 3);
  CHECK_FALSE(files[0].chosen); // OUT: the user's name
  CHECK(files[1].chosen);
  CHECK(files[1].path == t.path("cal.mid-2.tnet"));
  CHECK(files[2].path == t.path("cal.params-2.tnet")); // a dangling symlink is skipped too
  CHECK(files[0].text.find("include \"cal.mid-2.tnet\"") != std::string::npos);
  std::vector<app::OutputFile> out;
  for (const auto& f : files)
    out.push_back({f.path, f.text, f.chosen ? app::Follow::never : app::Follow::symlinks});
  app::write_output_files(out);
  CHECK(read(t.dir.path / "elsewhere/victim.txt") == "victim\n");
  CHECK(fs::is_symlink(t.path("cal.mid.tnet")));
  CHECK_FALSE(fs::exists(t.dir.path / "nowhere"));
  Loaded back(t.path("cal.tnet"));
  back.model->lint(back.diags);
  CHECK(back.diags.error_count() == 0);
  // A regular file at a chosen name (an earlier run's copy) is replaced, by a rename: a hard link
  // to it elsewhere keeps its content.
  fs::create_hard_link(t.path("cal.mid-2.tnet"), t.path("elsewhere/hard.tnet"));
  const std::string before = read(t.dir.path / "elsewhere/hard.tnet");
  std::vector<rewrite::ParamUpdate> other = updates;
  for (auto& u : other)
    u.value *= 2;
  files = rewrite::rewrite_model(m.sources, m.root(), other, t.path("cal.tnet"));
  REQUIRE(files.size() == 3);
  CHECK(files[1].path == t.path("cal.mid-2.tnet"));
  out.clear();
  for (const auto& f : files)
    out.push_back({f.path, f.text, f.chosen ? app::Follow::never : app::Follow::symlinks});
  app::write_output_files(out);
  CHECK(read(t.dir.path / "elsewhere/hard.tnet") == before);
  // Should a symlink appear at a chosen name after the names were chosen, the write refuses it.
  fs::remove(t.path("cal.params-2.tnet"));
  fs::create_symlink(t.path("elsewhere/victim.txt"), t.path("cal.params-2.tnet"));
  CHECK_THROWS_AS(app::write_output_files({{t.path("cal.params-2.tnet"), "x", app::Follow::never}}),
                  app::OutputError);
  CHECK(read(t.dir.path / "elsewhere/victim.txt") == "victim\n");
  // The user's own name is followed, as a shell redirection would.
  app::write_output_files({{t.path("cal.params-2.tnet"), "through\n"}});
  CHECK(read(t.dir.path / "elsewhere/victim.txt") == "through\n");
}

TEST_CASE("format_param_value: an expression keeps the one unit it is written in") {
  lang::ParamInfo k;
  k.dim = lang::dim::conductivity;
  CHECK(rewrite::format_param_value("2 * 1.25 [W/(m*K)]", k, 3.5) == "3.5 [W/(m*K)]");
  lang::ParamInfo len;
  len.dim = lang::dim::length;
  CHECK(rewrite::format_param_value("3 [mm] + 0.5 [mm]", len, 0.004) == "4 [mm]");
  CHECK(rewrite::format_param_value("1 [mm] + 1 [cm]", len, 0.011) == "0.011 [m]"); // two units: SI
  lang::ParamInfo ratio;
  ratio.dim = lang::Dimension{};
  CHECK(rewrite::format_param_value("2 [mm] / 1 [mm]", ratio, 1.5) == "1.5");
  lang::ParamInfo bare;
  CHECK(rewrite::format_param_value("k0 * 1.1", bare, 0.25) == "0.25");
}

TEST_CASE("files_read: the model, its includes, then its data, each with its role") {
  Tree t;
  Loaded m(t.path("main.tnet"));
  std::map<std::string, std::string> roles;
  for (const auto& f : rewrite::files_read(m.sources, m.root()))
    roles[fs::weakly_canonical(f.path).string()] = f.role;
  auto role = [&](const std::string& name) {
    auto it = roles.find(fs::weakly_canonical(t.path(name)).string());
    return it == roles.end() ? std::string("(missing)") : it->second;
  };
  CHECK(roles.size() == 5);
  CHECK(role("main.tnet") == "the model");
  CHECK(role("lib/mid.tnet") == "the included file");
  CHECK(role("lib/params.tnet") == "the included file");
  CHECK(role("geometry.tnet") == "the included file");
  CHECK(role("heat.csv") == "the data file");

  // Given the loaded model's syntax trees (as the CLI does), the same files in the same order.
  std::vector<const lang::ast::File*> parsed;
  for (const auto& file : m.model->files())
    parsed.push_back(file.get());
  REQUIRE(parsed.size() == 4);
  const auto fresh = rewrite::files_read(m.sources, m.root());
  const auto reused = rewrite::files_read(m.sources, m.root(), parsed);
  REQUIRE(reused.size() == fresh.size());
  for (std::size_t i = 0; i < fresh.size(); ++i) {
    CHECK(reused[i].path == fresh[i].path);
    CHECK(reused[i].role == fresh[i].role);
  }
}

TEST_CASE("write_output_files: all or nothing") {
  TempDir dir{"atomic"};
  const std::string a = (dir.path / "a.txt").string();
  fs::create_directories(dir.path / "b.txt");
  CHECK_THROWS_AS(app::write_output_files({{a, "A\n"}, {(dir.path / "b.txt").string(), "B\n"}}),
                  app::OutputError);
  CHECK_FALSE(fs::exists(a));
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path))
    ++entries;
  CHECK(entries == 1); // only the directory b.txt: no temporary file left
  CHECK_THROWS_AS(app::write_output_files({{a, "1"}, {(dir.path / "." / "a.txt").string(), "2"}}),
                  app::OutputError);
  CHECK_FALSE(fs::exists(a));
  app::write_output_files({{a, "A\n"}, {(dir.path / "c.txt").string(), "C\n"}});
  CHECK(read(a) == "A\n");
  CHECK(read(dir.path / "c.txt") == "C\n");
}
