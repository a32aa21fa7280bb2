// `monohydra compare`, run as a user runs it: the table's numbers are the
// runs' CSVs' numbers, the report and CSVs are written, a formulation that
// fails is in the table with its reason while the others run, and the
// default job compares the paper's case studies with the paper's numbers
// beside ours.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "printed_table.hpp"
#include "report_figures.hpp"

namespace mh::test {
namespace {

namespace fs = std::filesystem;

double number(const std::string& cell) {
  size_t used = 0;
  const double v = std::stod(cell, &used);
  EXPECT_EQ(used, cell.size()) << "not a number: '" << cell << "'";
  return v;
}

// The printed cell holds `value` to the digits it shows (%.4g or more).
void expect_printed(const PrintedTable& t, const std::string& label, const std::string& column,
                    double value) {
  const std::string cell = t.cell(label, column);
  ASSERT_FALSE(cell.empty()) << label << " / " << column;
  EXPECT_NEAR(number(cell), value, 5e-4 * std::abs(value) + 1e-300)
      << label << " / " << column << ": printed " << cell;
}

// Every number of the table recomputed from the CSVs in `dir`, the first
// formulation the reference of the differences.
void expect_table_from_csvs(const PrintedTable& t, const fs::path& dir,
                            const std::vector<std::string>& formulations) {
  const Csv ref = read_csv(dir / (formulations.front() + ".csv"));
  for (const auto& f : formulations) {
    SCOPED_TRACE(f);
    const Csv csv = read_csv(dir / (f + ".csv"));
    ASSERT_GT(csv.rows, 1u);
    const size_t steps = csv.rows - 1;
    double iterations = 0.0, max_iterations = 0.0, step_wall = 0.0, worst_wall = 0.0, worst_t = 0.0;
    for (size_t k = 1; k < csv.rows; ++k) {
      iterations += csv["iters"][k];
      max_iterations = std::max(max_iterations, csv["iters"][k]);
      step_wall += csv["wall_s"][k];
      if (csv["wall_s"][k] > worst_wall) {  // every step is a row here
        worst_wall = csv["wall_s"][k];
        worst_t = csv["t"][k];
      }
    }
    const double wall = csv["wall_s"][0] + step_wall;
    double drift = 0.0, drift_t = 0.0, work = 0.0, phi = 0.0;
    for (size_t k = 0; k < csv.rows; ++k) {
      if (std::abs(csv["drift"][k]) > drift) {
        drift = std::abs(csv["drift"][k]);
        drift_t = csv["t"][k];
      }
      work = std::max(work, std::abs(csv["W"][k]));
      phi = std::max(phi, csv["phi_norm"][k]);
    }
    double dz = 0.0;
    for (const auto& name : csv.header)
      if (name.size() > 1 && name[0] == 'z')
        for (size_t k = 0; k < std::min(csv.rows, ref.rows); ++k)
          dz = std::max(dz, std::abs(csv[name][k] - ref[name][k]));

    // Pressures (the hydraulic models' p1, p2, p3 columns).
    for (const auto& name : csv.header) {
      if (name.size() < 2 || name[0] != 'p' ||
          name.find_first_not_of("0123456789", 1) != std::string::npos)
        continue;
      double dp = 0.0;
      for (size_t k = 0; k < std::min(csv.rows, ref.rows); ++k)
        dp = std::max(dp, std::abs(csv[name][k] - ref[name][k]));
      const std::string label = "max |d" + name + "| from " + formulations.front() + " (Pa)";
      if (f == formulations.front())
        EXPECT_EQ(number(t.cell(label, f)), 0.0) << label;
      else
        expect_printed(t, label, f, dp);
    }
    EXPECT_EQ(t.cell("status", f), "ok");
    EXPECT_EQ(t.cell("steps", f), std::to_string(steps));
    EXPECT_NEAR(number(t.cell("Newton iterations avg", f)), iterations / static_cast<double>(steps),
                5e-5);
    EXPECT_EQ(number(t.cell("Newton iterations max", f)), max_iterations);
    expect_printed(t, "total wall time (s)", f, wall);
    expect_printed(t, "time per step (ms)", f, step_wall / static_cast<double>(steps) * 1e3);
    expect_printed(t, "worst step time (ms)", f, worst_wall * 1e3);
    expect_printed(t, "worst step at t (s)", f, worst_t);
    expect_printed(t, "real-time factor", f, csv["t"].back() / wall);
    expect_printed(t, "peak |drift| (J)", f, drift);
    expect_printed(t, "peak |drift| at t (s)", f, drift_t);
    if (work > 0.0) {
      expect_printed(t, "max |W| (J)", f, work);
      expect_printed(t, "peak |drift| (% of max |W|)", f, drift / work * 100.0);
    } else {
      EXPECT_EQ(t.cell("max |W| (J)", f), "0");
      EXPECT_EQ(t.cell("peak |drift| (% of max |W|)", f), "n/a");
    }
    expect_printed(t, "max phi_norm", f, phi);
    expect_printed(t, "max |dz| from " + formulations.front(), f, dz);
  }
}

TEST(Compare, TableNumbersAreComputedFromTheRunsCsvsOnTheFourBar) {
  const fs::path dir = scratch_dir("table-fourbar");
  const CliResult r =
      run_cli("compare " + shipped_model("fourbar-free.yaml") +
              " --formulations double-step,penalty --t-end 3 --report " + dir.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const PrintedTable t = parse_printed_table(r.output, "fourbar-free (");
  ASSERT_TRUE(t.found) << r.output;
  EXPECT_EQ(t.header, (std::vector<std::string>{"quantity", "double-step", "penalty"}));
  expect_table_from_csvs(t, dir, {"double-step", "penalty"});
  // The two formulations really differ (penalty holds the loop less tightly),
  // so the differences row is not trivially zero.
  EXPECT_GT(number(t.cell("max |dz| from double-step", "penalty")), 0.0);
  EXPECT_EQ(number(t.cell("max |dz| from double-step", "double-step")), 0.0);
}

TEST(Compare, DriftPercentIsOfTheMaximumWorkWhenSubsystemsDoWork) {
  // The Maxwell element does work on the pendulum, so max |W| > 0.
  const fs::path dir = scratch_dir("table-maxwell");
  const CliResult r =
      run_cli("compare " + shipped_model("maxwell-pendulum.yaml") +
              " --formulations open-loop,penalty --t-end 2 --report " + dir.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const PrintedTable t = parse_printed_table(r.output, "maxwell-pendulum (");
  ASSERT_TRUE(t.found) << r.output;
  ASSERT_NE(t.cell("max |W| (J)", "open-loop"), "0");
  expect_table_from_csvs(t, dir, {"open-loop", "penalty"});
}

TEST(Compare, WritesTheReportAndOneCsvPerFormulationForBothMechanisms) {
  for (const char* model : {"fourbar-free", "quickreturn-free"}) {
    SCOPED_TRACE(model);
    const fs::path dir = scratch_dir(std::string("report-") + model);
    const CliResult r =
        run_cli("compare " + shipped_model(std::string(model) + ".yaml") +
                " --formulations double-step,penalty --t-end 2 --report " + dir.string());
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("report: " + (dir / "report.html").string()), std::string::npos)
        << r.output;
    EXPECT_TRUE(parse_printed_table(r.output, std::string(model) + " (").found) << r.output;
    EXPECT_GT(fs::file_size(dir / "report.html"), 10000u);
    for (const char* f : {"double-step", "penalty"}) {
      const Csv csv = read_csv(dir / (std::string(f) + ".csv"));
      EXPECT_EQ(csv.rows, 2001u) << f;
      EXPECT_EQ(csv.header.back(), "wall_s");
    }
  }
}

TEST(Compare, CsvIsTheRunCommandsCsvWithTheWallTimeAppended) {
  const fs::path dir = scratch_dir("same-as-run");
  const std::string model = shipped_model("fourbar-free.yaml");
  ASSERT_EQ(run_cli("run " + model + " --t-end 0.5 --out " + (dir / "run.csv").string()).code, 0);
  ASSERT_EQ(run_cli("compare " + model + " --formulations double-step --t-end 0.5 --report " +
                    (dir / "cmp").string())
                .code,
            0);
  const std::string run_text = read_text(dir / "run.csv");
  const std::string cmp_text = read_text(dir / "cmp" / "double-step.csv");
  // Drop the last column of every line of the comparison's CSV.
  std::string stripped;
  size_t begin = 0;
  while (begin < cmp_text.size()) {
    const size_t end = cmp_text.find('\n', begin);
    const std::string line = cmp_text.substr(begin, end - begin);
    stripped += line.substr(0, line.rfind(',')) + '\n';
    begin = end + 1;
  }
  EXPECT_EQ(stripped, run_text);
}

// The double pendulum with `extra` appended (an output: block).
std::string pendulum_with(const fs::path& folder, const std::string& extra) {
  const fs::path path = folder / "pendulum.yaml";
  std::ofstream(path) << read_text(shipped_model("double-pendulum.yaml")) << extra;
  return path.string();
}

// Each line of a comparison's CSV without its last column (wall_s).
std::string without_wall_column(const std::string& text) {
  std::string stripped;
  size_t begin = 0;
  while (begin < text.size()) {
    const size_t end = text.find('\n', begin);
    const std::string line = text.substr(begin, end - begin);
    stripped += line.substr(0, line.rfind(',')) + '\n';
    begin = end + 1;
  }
  return stripped;
}

TEST(Compare, HonoursTheModelFilesOutputIntervalAndColumnsLikeRun) {
  const fs::path dir = scratch_dir("output-block");
  const std::string model =
      pendulum_with(dir, "output: {interval: 0.05, columns: [t, z2, KE, drift]}\n");
  ASSERT_EQ(run_cli("run " + model + " --t-end 0.5 --out " + (dir / "run.csv").string()).code, 0);
  const CliResult r =
      run_cli("compare " + model + " --t-end 0.5 --report " + (dir / "cmp").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string cmp_text = read_text(dir / "cmp" / "open-loop.csv");
  EXPECT_EQ(cmp_text.substr(0, cmp_text.find('\n')), "t,z2,KE,drift,wall_s");
  // Row for row the run's: 11 rows at multiples of 50 ms.
  EXPECT_EQ(without_wall_column(cmp_text), read_text(dir / "run.csv"));
  EXPECT_EQ(read_csv(dir / "cmp" / "open-loop.csv").rows, 11u);
  // The table counts the steps, not the rows: 500 steps of 1 ms.
  EXPECT_NE(r.output.find("500"), std::string::npos) << r.output;
}

TEST(Compare, MaxOutputBytesCountsOnlyTheRowsWritten) {
  const fs::path dir = scratch_dir("output-bytes");
  // 10 s at 1 ms: 10001 rows of every step are ~2.4 MB; one row per 0.1 s, 101 rows, ~25 kB.
  const std::string sparse = pendulum_with(dir, "output: {interval: 0.1}\n");
  const std::string every = shipped_model("double-pendulum.yaml");
  for (const std::string command : {"compare ", "run "}) {
    const std::string out =
        command == "run " ? " --out " + (dir / "r.csv").string() : std::string();
    const CliResult ok = run_cli(command + sparse + " --max-output-bytes 1e5" + out);
    EXPECT_EQ(ok.code, 0) << command << ok.output;
    const CliResult refused = run_cli(command + every + " --max-output-bytes 1e5" + out);
    // run refuses to start (2); compare reports the run as failed at setup (1).
    EXPECT_EQ(refused.code, command == "run " ? 2 : 1) << command << refused.output;
    EXPECT_NE(refused.output.find("10001 rows"), std::string::npos) << refused.output;
    EXPECT_NE(refused.output.find("above the limit of 100000 bytes"), std::string::npos)
        << refused.output;
  }
}

TEST(Compare, IntegratorsAloneVaryTheRunsAreNamedAfterThemAndAgreeToTheirOrder) {
  const fs::path dir = scratch_dir("integrators");
  const CliResult r = run_cli("compare " + shipped_model("fourbar-free.yaml") +
                              " --formulations penalty"
                              " --integrators trapezoidal,generalized-alpha,bdf2 --t-end 1"
                              " --report " +
                              dir.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const PrintedTable t = parse_printed_table(r.output, "fourbar-free (");
  ASSERT_TRUE(t.found) << r.output;
  EXPECT_EQ(t.header,
            (std::vector<std::string>{"quantity", "trapezoidal", "generalized-alpha", "bdf2"}));
  expect_table_from_csvs(t, dir, {"trapezoidal", "generalized-alpha", "bdf2"});
  // Three second-order methods at dt = 1 ms: they differ, but by far less than
  // the motion (the four-bar swings by ~1 rad in the first second).
  for (const char* i : {"generalized-alpha", "bdf2"}) {
    const double dz = number(t.cell("max |dz| from trapezoidal", i));
    EXPECT_GT(dz, 0.0) << i;
    EXPECT_LT(dz, 1e-3) << i;
  }
  EXPECT_EQ(t.cell("status", "bdf2"), "ok");
  EXPECT_NE(
      read_text(dir / "report.html").find("integrators: trapezoidal, generalized-alpha, bdf2"),
      std::string::npos);
}

TEST(Compare, FormulationsAndIntegratorsBothVaryEveryPairRunsNamedFPlusI) {
  const fs::path dir = scratch_dir("both-vary");
  const CliResult r = run_cli("compare " + shipped_model("fourbar-free.yaml") +
                              " --formulations double-step,penalty --integrators trapezoidal,bdf2"
                              " --t-end 0.2 --report " +
                              dir.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const PrintedTable t = parse_printed_table(r.output, "fourbar-free (");
  ASSERT_TRUE(t.found) << r.output;
  const std::vector<std::string> labels{"double-step+trapezoidal", "double-step+bdf2",
                                        "penalty+trapezoidal", "penalty+bdf2"};
  EXPECT_EQ(t.header,
            (std::vector<std::string>{"quantity", labels[0], labels[1], labels[2], labels[3]}));
  for (const auto& l : labels) EXPECT_EQ(read_csv(dir / (l + ".csv")).rows, 201u) << l;
  // The same integrator under both formulations agrees closely.
  EXPECT_LT(number(t.cell("max |dz| from double-step+trapezoidal", "penalty+trapezoidal")), 1e-6);
}

TEST(Compare, WithoutListsTheModelFilesCompareSectionChoosesElseItsOwnChoice) {
  const fs::path dir = scratch_dir("defaults");
  std::string text = read_text(shipped_model("fourbar-free.yaml"));
  const std::string line = "formulation: {name: double-step}";
  ASSERT_NE(text.find(line), std::string::npos);
  const fs::path plain = dir / "plain.yaml";
  std::ofstream(plain) << text;
  text.replace(text.find(line), line.size(),
               line + "\ncompare: {formulations: [penalty, double-step], integrators: [bdf2]}");
  const fs::path listed = dir / "listed.yaml";
  std::ofstream(listed) << text;
  const CliResult a = run_cli("compare " + plain.string() + " --t-end 0.05");
  ASSERT_EQ(a.code, 0) << a.output;
  EXPECT_EQ(parse_printed_table(a.output, "fourbar-free (").header,
            (std::vector<std::string>{"quantity", "double-step"}));
  const CliResult b = run_cli("compare " + listed.string() + " --t-end 0.05");
  ASSERT_EQ(b.code, 0) << b.output;
  EXPECT_EQ(parse_printed_table(b.output, "fourbar-free (").header,
            (std::vector<std::string>{"quantity", "penalty", "double-step"}));
  // The command line wins over the file.
  const CliResult c = run_cli("compare " + listed.string() + " --integrators trapezoidal,bdf2" +
                              " --formulations penalty --t-end 0.05");
  ASSERT_EQ(c.code, 0) << c.output;
  EXPECT_EQ(parse_printed_table(c.output, "fourbar-free (").header,
            (std::vector<std::string>{"quantity", "trapezoidal", "bdf2"}));
}

TEST(Compare, AnUnknownIntegratorIsAFailedRunAndTheExitStatusIsOne) {
  const fs::path dir = scratch_dir("bad-integrator");
  const CliResult r =
      run_cli("compare " + shipped_model("fourbar-free.yaml") +
              " --integrators trapezoidal,rk99 --t-end 0.05 --report " + dir.string());
  EXPECT_EQ(r.code, 1) << r.output;
  const PrintedTable t = parse_printed_table(r.output, "fourbar-free (");
  ASSERT_TRUE(t.found) << r.output;
  EXPECT_EQ(t.cell("status", "trapezoidal"), "ok");
  EXPECT_EQ(t.cell("status", "rk99"), "FAILED at setup");
  EXPECT_TRUE(fs::exists(dir / "report.html"));
  EXPECT_NE(r.output.find("unknown integrator 'rk99'"), std::string::npos) << r.output;
}

TEST(Compare, AFailingFormulationIsInTheTableWithItsReasonAndTheOthersStillRun) {
  const fs::path dir = scratch_dir("failing");
  // double-step with a re-partition threshold too low for the crank-rocker
  // stops at t = 0.434 s (tests/plugins/formulations/double_step_test.cpp); 'lagrange' is
  // no formulation at all.
  std::string text = read_text(shipped_model("crank-rocker.yaml"));
  const std::string line = "formulation: {name: double-step}";
  ASSERT_NE(text.find(line), std::string::npos);
  text.replace(text.find(line), line.size(),
               "formulation: {name: double-step, independent_coordinates: z3, "
               "repartition_rcond: 0.001}");
  const fs::path model = dir / "crank-rocker-late.yaml";
  std::ofstream(model) << text;
  const CliResult r = run_cli("compare " + model.string() +
                              " --formulations double-step,lagrange,penalty --t-end 1 --report " +
                              (dir / "report").string());
  EXPECT_EQ(r.code, 1) << r.output;
  const PrintedTable t = parse_printed_table(r.output, "crank-rocker (");
  ASSERT_TRUE(t.found) << r.output;
  EXPECT_EQ(t.cell("status", "double-step"), "FAILED at t = 0.434 s");
  EXPECT_EQ(t.cell("status", "lagrange"), "FAILED at setup");
  EXPECT_EQ(t.cell("status", "penalty"), "ok");
  EXPECT_EQ(t.cell("steps", "double-step"), "433");  // the rows before the failure
  EXPECT_EQ(t.cell("steps", "lagrange"), "-");
  EXPECT_EQ(t.cell("steps", "penalty"), "1000");
  // Each failure's reason is under the table.
  auto note = [&t](const std::string& start) {
    for (const auto& n : t.notes)
      if (n.rfind(start, 0) == 0) return n;
    return std::string();
  };
  EXPECT_NE(note("double-step FAILED: t = 0.434 s, step 434: ").find("det Phi_z^d changed sign"),
            std::string::npos)
      << r.output;
  EXPECT_NE(note("lagrange FAILED: ").find("unknown formulation 'lagrange'"), std::string::npos)
      << r.output;
  // The others still report: CSVs of the rows they have, and the report.
  EXPECT_EQ(read_csv(dir / "report" / "double-step.csv").rows, 434u);
  EXPECT_EQ(read_csv(dir / "report" / "penalty.csv").rows, 1001u);
  EXPECT_FALSE(fs::exists(dir / "report" / "lagrange.csv"));
  const std::string html = read_text(dir / "report" / "report.html");
  EXPECT_NE(html.find("FAILED at t = 0.434 s"), std::string::npos);
  EXPECT_NE(html.find("unknown formulation &#39;lagrange&#39;"), std::string::npos);
}

TEST(Compare, WhenEveryFormulationFailsTheTableAndReportStillSayWhy) {
  const fs::path dir = scratch_dir("all-failing");
  // open-loop refuses cut joints; 'lagrange' does not exist.
  const CliResult r = run_cli("compare " + shipped_model("fourbar-free.yaml") +
                              " --formulations open-loop,lagrange --report " + dir.string());
  EXPECT_EQ(r.code, 1) << r.output;
  const PrintedTable t = parse_printed_table(r.output, "fourbar-free (");
  ASSERT_TRUE(t.found) << r.output;
  EXPECT_EQ(t.cell("status", "open-loop"), "FAILED at setup");
  EXPECT_EQ(t.cell("status", "lagrange"), "FAILED at setup");
  ASSERT_EQ(t.notes.size(), 2u) << r.output;
  EXPECT_NE(t.notes[0].find("open-loop handles trees only"), std::string::npos) << t.notes[0];
  const std::string html = read_text(dir / "report.html");
  EXPECT_NE(html.find("No run produced results"), std::string::npos);
  EXPECT_EQ(html.find("<svg"), std::string::npos);
}

TEST(Compare, BadArgumentsExitWithTwo) {
  const std::string model = shipped_model("fourbar-free.yaml");
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {"compare", "compare needs a model file"},
           {"compare " + model + " --formulations penalty,penalty", "names 'penalty' twice"},
           {"compare " + model + " --formulations ,", "expects names separated by commas"},
           {"compare " + model + " --t-end soon", "--t-end expects a number, got 'soon'"},
           {"compare " + model + " --frobnicate", "unknown option '--frobnicate'"},
           {"compare /no/such/model.yaml", "/no/such/model.yaml"}}) {
    const CliResult r = run_cli(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << args << "\n" << r.output;
  }
}

// The shipped case studies with their models swapped for the free
// mechanisms (the hydraulic ones are not on this branch yet).
fs::path free_case_studies(const fs::path& dir) {
  std::string text = read_text(shipped_model("paper-reference.yaml"));
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"model: fourbar.yaml", "model: " + shipped_model("fourbar-free.yaml")},
           {"model: quickreturn.yaml", "model: " + shipped_model("quickreturn-free.yaml")}}) {
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  }
  const fs::path file = dir / "case-studies.yaml";
  std::ofstream(file) << text;
  return file;
}

// The README's main command: no arguments, the paper's two hydraulic case
// studies, both formulations, the paper's numbers beside ours.
TEST(Compare, DefaultJobComparesBothCaseStudiesWithThePapersNumbersBeside) {
  const fs::path dir = scratch_dir("default-job");
  const CliResult r = run_cli("", "", dir.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const PrintedTable fourbar = parse_printed_table(r.output, "four-bar (");
  const PrintedTable quick = parse_printed_table(r.output, "quick-return (");
  ASSERT_TRUE(fourbar.found) << r.output;
  ASSERT_TRUE(quick.found) << r.output;
  const std::vector<std::string> header{"quantity", "double-step", "paper", "penalty", "paper"};
  EXPECT_EQ(fourbar.header, header);
  EXPECT_EQ(quick.header, header);
  // The paper's numbers (../shared/case-studies.md, last table) beside ours.
  EXPECT_EQ(fourbar.cell("Newton iterations avg", "paper", 0), "1.39");
  EXPECT_EQ(fourbar.cell("Newton iterations max", "paper", 1), "4");
  EXPECT_EQ(fourbar.cell("total wall time (s)", "paper", 1), "21.54");
  EXPECT_EQ(fourbar.cell("max |W| (J)", "paper", 0), "982.95");
  EXPECT_EQ(fourbar.cell("peak |drift| (J)", "paper", 0), "0.84");
  EXPECT_EQ(fourbar.cell("peak |drift| (% of max |W|)", "paper", 0), "0.09");
  EXPECT_EQ(quick.cell("Newton iterations avg", "paper", 0), "1.49");
  EXPECT_EQ(quick.cell("Newton iterations max", "paper", 1), "6");
  EXPECT_EQ(quick.cell("total wall time (s)", "paper", 0), "29.03");
  EXPECT_EQ(quick.cell("max |W| (J)", "paper", 1), "357.47");
  EXPECT_EQ(quick.cell("peak |drift| (J)", "paper", 1), "0.23");
  // Ours are the runs' (10 s of the model's settings).
  EXPECT_EQ(fourbar.cell("steps", "double-step"), "10000");
  EXPECT_EQ(quick.cell("steps", "penalty"), "10000");
  // And it says where the reports are.
  for (const char* name : {"fourbar", "quickreturn"}) {
    const fs::path report = dir / "out" / name / "report.html";
    EXPECT_TRUE(fs::exists(report)) << report;
    EXPECT_NE(r.output.find("  " + report.string()), std::string::npos) << r.output;
    EXPECT_TRUE(fs::exists(dir / "out" / name / "penalty.csv"));
    // With the paper's Newton (paper-reference.yaml), not the models' default.
    for (const char* run : {"double-step", "penalty"}) {
      const std::string meta = read_text(dir / "out" / name / (std::string(run) + ".meta.json"));
      EXPECT_NE(meta.find("\"newton\": \"full\""), std::string::npos) << name << ' ' << run;
    }
  }
  // Double-step's own partition, beside the paper's (Sect. 6.1).
  EXPECT_EQ(fourbar.cell("coordinates in use", "double-step"), "z3 throughout");
  EXPECT_EQ(fourbar.cell("coordinates in use", "paper", 0), "z3 throughout");
  EXPECT_EQ(quick.cell("coordinates in use", "double-step"), "z4 throughout");
  EXPECT_EQ(quick.cell("coordinates in use", "penalty"), "-");
  // Every number of both tables from the runs' CSVs, pressures included.
  expect_table_from_csvs(fourbar, dir / "out" / "fourbar", {"double-step", "penalty"});
  expect_table_from_csvs(quick, dir / "out" / "quickreturn", {"double-step", "penalty"});
  EXPECT_FALSE(fourbar.cell("max |dp2| from double-step (Pa)", "penalty").empty());
  // The hydraulic report: pressures of both runs, the valve's two openings
  // shaded on the time plots, the cylinder drawn at every second.
  const std::string html = read_text(dir / "out" / "fourbar" / "report.html");
  const auto count = [&html](const std::string& what) {
    size_t n = 0;
    for (size_t at = html.find(what); at != std::string::npos; at = html.find(what, at + 1)) ++n;
    return n;
  };
  for (const auto& id : mh::cli::report_figure_ids())
    EXPECT_NE(html.find("<figure id=\"" + id + "\">"), std::string::npos) << id;
  EXPECT_EQ(html.find("no pressures"), std::string::npos);
  EXPECT_GE(count("<rect class=\"shade\""), 2u * 7u);  // 2 openings on each time plot
}

// The excavator (a 3D machine, docs/machines.md) by its compare defaults,
// the first second of its cycle: one CSV per formulation with a row per
// step, and a report whose mechanism drawing has the three views, with the
// pressures of every circuit, the strokes, forces and the pump's power.
TEST(Compare, ExcavatorWritesBothCsvsAndAReportDrawingTheMachineInThreeViews) {
  const fs::path dir = scratch_dir("excavator");
  const CliResult r = run_cli("compare " + shipped_model("excavator.yaml") +
                              " --t-end 0.2 --report " + (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* csv : {"double-step.csv", "penalty.csv"}) {
    const std::string text = read_text(dir / "out" / csv);
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1 + 201)
        << csv;  // header, t = 0, 200 steps
  }
  const std::string html = read_text(dir / "out" / "report.html");
  for (const char* view : {">side view<", ">top view<", ">isometric view<"})
    EXPECT_NE(html.find(view), std::string::npos) << view;
  for (const char* title :
       {"<title>p_supply double-step</title>", "<title>p_slew_b penalty</title>",
        "<title>s_boom_l double-step</title>", "<title>F_bucket penalty</title>",
        "<title>P_pump double-step</title>"})
    EXPECT_NE(html.find(title), std::string::npos) << title;
}

TEST(Compare, DefaultJobStopsWithAClearMessageWhenAModelIsMissing) {
  const fs::path dir = scratch_dir("default-job-missing");
  std::string text = read_text(shipped_model("paper-reference.yaml"));
  const std::string from = "model: quickreturn.yaml";
  text.replace(text.find(from), from.size(), "model: " + shipped_model("fourbar-free.yaml"));
  std::ofstream(dir / "studies.yaml") << text;  // four-bar: fourbar.yaml beside it, missing
  const CliResult r =
      run_cli("", "MONOHYDRA_CASE_STUDIES=" + (dir / "studies.yaml").string() + " ", dir.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(
      r.output.find("the model of the four-bar is missing: " + (dir / "fourbar.yaml").string()),
      std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "out")) << "nothing runs before every model is found";
}

TEST(Compare, AModelOfACaseStudyGetsThePapersNumbersBesideOurs) {
  const fs::path dir = scratch_dir("compare-case-study");
  const fs::path studies = free_case_studies(dir);
  const CliResult r = run_cli("compare " + shipped_model("fourbar-free.yaml") +
                                  " --formulations penalty,open-loop --t-end 0.2",
                              "MONOHYDRA_CASE_STUDIES=" + studies.string() + " ");
  EXPECT_EQ(r.code, 1) << r.output;  // open-loop refuses a model with cut joints
  const PrintedTable t = parse_printed_table(r.output, "four-bar (");
  ASSERT_TRUE(t.found) << r.output;
  EXPECT_EQ(t.cell("Newton iterations max", "paper", 0), "4");  // beside penalty
  EXPECT_EQ(t.cell("Newton iterations max", "paper", 1), "-");  // the paper ran no open-loop
}

}  // namespace
}  // namespace mh::test
