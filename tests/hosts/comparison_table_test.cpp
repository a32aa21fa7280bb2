// The comparison table (hosts/monohydra/comparison_table.cpp): quantities by
// formulation, failures marked with their reason, the paper's numbers beside
// the formulations it ran, and text that reads back cell by cell.
#include "comparison_table.hpp"

#include <gtest/gtest.h>

#include "printed_table.hpp"
#include "synthetic_run.hpp"

namespace mh::test {
namespace {

cli::RunRecord run(const std::string& formulation, double z_offset) {
  SyntheticRun s;
  s.formulation = formulation;
  s.z = {[z_offset](size_t, double t) { return t + z_offset; }};
  s.states = {{"p1", "Pa", [z_offset](size_t, double) { return 2e6 + 1e6 * z_offset; }}};
  s.iters = [](size_t k, double) { return k == 0 ? 0.0 : 2.0; };
  s.wall = [](size_t, double) { return 1e-3; };
  s.W = [](size_t, double t) { return 100.0 * t; };
  s.drift = [](size_t, double t) { return 0.01 * t; };
  return s.make();
}

cli::RunRecord failed_at_setup(const std::string& formulation) {
  cli::RunRecord r;
  r.formulation = formulation;
  r.label = formulation;
  r.failed = true;
  r.failure = "unknown formulation 'x' (found: a, b)";
  return r;
}

TEST(ComparisonTable, OneColumnPerFormulationAndDifferencesFromTheFirst) {
  const auto c = cli::summarize("m", "m.yaml", {run("a", 0.0), run("b", 0.001)});
  const cli::TextTable t = cli::comparison_table(c, nullptr);
  EXPECT_EQ(t.header, (std::vector<std::string>{"quantity", "a", "b"}));
  const PrintedTable p = parse_printed_table(cli::render_text(t), "m (m.yaml)");
  ASSERT_TRUE(p.found);
  EXPECT_EQ(p.cell("status", "b"), "ok");
  EXPECT_EQ(p.cell("Newton iterations avg", "a"), "2.0000");
  EXPECT_EQ(p.cell("max |W| (J)", "a"), "100");
  EXPECT_EQ(p.cell("peak |drift| (% of max |W|)", "a"), "0.01");
  EXPECT_EQ(p.cell("max |dz| from a", "a"), "0.000e+00");
  EXPECT_EQ(p.cell("max |dz| from a", "b"), "1.000e-03");
  EXPECT_EQ(p.cell("max |dp1| from a (Pa)", "b"), "1.000e+03");
}

TEST(ComparisonTable, AFailedFormulationShowsFailedWithItsReasonAndNoNumbers) {
  const auto c = cli::summarize("m", "m.yaml", {failed_at_setup("x"), run("b", 0.0)});
  const cli::TextTable t = cli::comparison_table(c, nullptr);
  const PrintedTable p = parse_printed_table(cli::render_text(t), "m (m.yaml)");
  ASSERT_TRUE(p.found);
  EXPECT_EQ(p.cell("status", "x"), "FAILED at setup");
  EXPECT_EQ(p.cell("steps", "x"), "-");
  EXPECT_EQ(p.cell("max phi_norm", "x"), "-");
  EXPECT_EQ(p.cell("steps", "b"), "10");
  // The differences are from the first run that has results.
  EXPECT_EQ(p.cell("max |dz| from b", "b"), "0.000e+00");
  ASSERT_GE(p.notes.size(), 2u);
  EXPECT_EQ(p.notes[0], "x FAILED: unknown formulation 'x' (found: a, b)");
  EXPECT_EQ(p.notes[1], "differences are from b, the first run with results");
}

TEST(ComparisonTable, ThePapersNumbersStandBesideTheFormulationsItRan) {
  cli::PaperNumbers paper;
  paper.source = "the paper";
  paper.max_actuator_work = 982.95;
  paper.integrator = "trapezoidal";
  paper.runs.push_back({"b", "", 1.39, 3.0, 27.45});
  const auto c = cli::summarize("m", "m.yaml", {run("a", 0.0), run("b", 0.0)});
  const cli::TextTable t = cli::comparison_table(c, &paper);
  EXPECT_EQ(t.header, (std::vector<std::string>{"quantity", "a", "paper", "b", "paper"}));
  const PrintedTable p = parse_printed_table(cli::render_text(t), "m (m.yaml)");
  EXPECT_EQ(p.cell("Newton iterations avg", "paper", 0), "-");  // the paper did not run a
  EXPECT_EQ(p.cell("Newton iterations avg", "paper", 1), "1.39");
  EXPECT_EQ(p.cell("Newton iterations max", "paper", 1), "3");
  EXPECT_EQ(p.cell("total wall time (s)", "paper", 1), "27.45");
  EXPECT_EQ(p.cell("max |W| (J)", "paper", 1), "982.95");
  EXPECT_EQ(p.cell("peak |drift| (J)", "paper", 1), "-");  // not given
  EXPECT_EQ(p.cell("time per step (ms)", "paper", 1), "-");
}

TEST(ComparisonTable, TextColumnsAreSeparatedByAtLeastTwoSpacesAndCellsAreNeverEmpty) {
  const auto c = cli::summarize("m", "m.yaml", {run("double-step", 0.0), failed_at_setup("x")});
  const cli::TextTable t = cli::comparison_table(c, nullptr);
  for (const auto& r : t.rows)
    for (const auto& cell : r) {
      EXPECT_FALSE(cell.empty());
      EXPECT_EQ(cell.find("  "), std::string::npos) << cell;
    }
  const PrintedTable p = parse_printed_table(cli::render_text(t), "m (m.yaml)");
  EXPECT_EQ(p.rows.size(), t.rows.size());
}

}  // namespace
}  // namespace mh::test
