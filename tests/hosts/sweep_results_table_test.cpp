// results.csv: fields that need quotes read back whole, a resumed table keeps
// its whole rows and cuts a torn last line, a table of another study is
// refused, and the finished table is in case order.
#include <gtest/gtest.h>

#include <fstream>

#include "cli_runner.hpp"
#include "results_table.hpp"

namespace mh::cli::sweep {
namespace {

namespace fs = std::filesystem;

Study small_study(const fs::path& dir) {
  std::ofstream(dir / "study.yaml")
      << "models:\n  - {name: fourbar, file: " << mh::test::shipped_model("fourbar.yaml")
      << "}\nparameters:\n  solver/dt: [0.001, 0.002, 0.005]\n";
  return load_study((dir / "study.yaml").string());
}

TEST(SweepResultsTable, FieldsWithCommasQuotesAndLineBreaksReadBackWhole) {
  const std::string reason = "t = 1 s, step 3: \"Newton\" failed\non a line";
  const auto fields = split_csv_line("a," + csv_field(reason) + ",3");
  ASSERT_EQ(fields.size(), 3u);
  EXPECT_EQ(fields[1], "t = 1 s, step 3: \"Newton\" failed on a line");
  EXPECT_EQ(csv_field("plain"), "plain");
}

TEST(SweepResultsTable, AResumedTableKeepsWholeRowsAndCutsATornLastLine) {
  const fs::path dir = mh::test::scratch_dir("sweep-table-resume");
  const Study study = small_study(dir);
  const auto cases = expand_cases(study);
  CaseOutcome ok;
  ok.status = "ok";
  ok.t_reached = 10.0;
  ok.metrics = {1.5, 2e-9, 100.0};
  std::string row2;
  {
    ResultsTable table(dir.string(), study, cases);
    table.append(2, format_row(study, cases[2], ok));
    row2 = format_row(study, cases[2], ok);
  }
  {  // a machine that stopped mid-write
    std::ofstream(dir / "results.csv", std::ios::app) << "0,fourbar,0.001,ok,,1";
  }
  ResultsTable table(dir.string(), study, cases);
  EXPECT_THROW(ResultsTable(dir.string(), study, cases), std::runtime_error);  // held
  EXPECT_TRUE(table.has(2));
  EXPECT_FALSE(table.has(0));
  EXPECT_EQ(table.rows(), 1u);
  const std::string text = mh::test::read_text(dir / "results.csv");
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(text.find("0,fourbar,0.001,ok,,1"), std::string::npos);
  table.append(0, format_row(study, cases[0], ok));
  table.append(1, format_row(study, cases[1], ok));
  table.finish();
  const std::string done = mh::test::read_text(dir / "results.csv");
  EXPECT_LT(done.find("\n0,"), done.find("\n1,"));  // case order after finish
  EXPECT_LT(done.find("\n1,"), done.find("\n2,"));
  EXPECT_NE(done.find(row2), std::string::npos);
}

TEST(SweepResultsTable, ATableOfAnotherStudyIsRefused) {
  const fs::path dir = mh::test::scratch_dir("sweep-table-other");
  const Study study = small_study(dir);
  const auto cases = expand_cases(study);
  std::ofstream(dir / "results.csv") << "case,model,solver/t_end\n";
  EXPECT_THROW(ResultsTable(dir.string(), study, cases), std::runtime_error);
  fs::remove(dir / "results.csv");  // now the same columns, but case 1 with another dt
  { ResultsTable table(dir.string(), study, cases); }
  std::ofstream(dir / "results.csv", std::ios::app) << "1,fourbar,0.003,ok,,10,1,1,1,0,0\n";
  EXPECT_THROW(ResultsTable(dir.string(), study, cases), std::runtime_error);
}

}  // namespace
}  // namespace mh::cli::sweep
