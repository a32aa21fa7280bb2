// monohydra estimate (hosts/monohydra/estimate/) as a user runs it: the
// four-bar's sensors (run --sensors-out) read off a machine whose force
// model differs from the file's, the file's model run as the filter on
// them, against the same model run open loop; and bad input refused
// before any row is written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "hosts/cli_runner.hpp"

namespace {

namespace fs = std::filesystem;
using mh::test::run_cli;

const std::string kFourbar = mh::test::shipped_model("fourbar.yaml");
// The machine: the load +10 %, the cylinder's friction loss doubled, the
// hoses' bulk modulus -20 %.
const std::string kMachine =
    " --set bodies/body3/mass=55 --set subsystems/cylinder/efficiency=0.76"
    " --set subsystems/V1/bulk_modulus=440e6 --set subsystems/V2/bulk_modulus=440e6"
    " --set subsystems/V3/bulk_modulus=440e6";

// Columns by name; an empty field is NaN.
std::map<std::string, std::vector<double>> read_columns(const fs::path& p) {
  std::map<std::string, std::vector<double>> out;
  std::ifstream in(p);
  std::string line;
  std::vector<std::string> header;
  if (!std::getline(in, line)) return out;
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) header.push_back(cell);
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string cell;
    for (size_t c = 0; c < header.size(); ++c) {
      if (!std::getline(ss, cell, ',')) cell.clear();
      out[header[c]].push_back(cell.empty() ? NAN : std::stod(cell));
    }
  }
  return out;
}

double rms_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(sum / static_cast<double>(a.size()));
}

TEST(EstimateCommand, TheFourBarsOwnSensorsBringItsEstimateTenTimesCloserToTheMachine) {
  const fs::path dir = mh::test::scratch_dir("estimate-tracks");
  const fs::path data = dir / "sensors.csv", truth = dir / "truth.csv", open = dir / "open.csv",
                 estimated = dir / "estimated.csv";
  auto r = run_cli("run " + kFourbar + kMachine + " --t-end 4 --seed 3 --sensors-out " +
                   data.string() + " --out " + truth.string());
  ASSERT_EQ(r.code, 0) << r.output;
  r = run_cli("run " + kFourbar + " --t-end 4 --out " + open.string());
  ASSERT_EQ(r.code, 0) << r.output;
  r = run_cli("estimate " + kFourbar + " --measurements " + data.string() + " --out " +
              estimated.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto t = read_columns(truth), o = read_columns(open), e = read_columns(estimated);
  ASSERT_EQ(e.at("t").size(), t.at("t").size());  // to the last sample, every step
  // The mechanism (the encoder at 1e-4 rad, 1 kHz): a hundred times closer;
  // the pressures (transducers at 0.5 % of the supply, 100 Hz) over seven.
  for (const char* column : {"z1", "z3", "s"})
    EXPECT_LT(rms_difference(e.at(column), t.at(column)),
              0.01 * rms_difference(o.at(column), t.at(column)))
        << column;
  for (const char* column : {"p1", "p2", "p3"})
    EXPECT_LT(rms_difference(e.at(column), t.at(column)),
              0.15 * rms_difference(o.at(column), t.at(column)))
        << column;
  // Each state's standard deviation, each sensor's innovation where it had
  // a sample (the pressures every tenth step), and the NIS.
  for (const char* column :
       {"z3_sd", "z3_dot_sd", "p2_sd", "z1_innovation", "p2_innovation_sd", "nis", "samples"})
    EXPECT_EQ(e.count(column), 1U) << column;
  EXPECT_TRUE(std::isnan(e.at("p2_innovation")[1]));
  EXPECT_FALSE(std::isnan(e.at("p2_innovation")[10]));
  // The filter's own p2 standard deviation against the error it makes:
  // the same order (honest to a factor of three).
  const double sd = e.at("p2_sd").back(), error = rms_difference(e.at("p2"), t.at("p2"));
  EXPECT_GT(sd, error / 3.0);
  EXPECT_LT(sd, error * 3.0);
  // The unscented filter on the same data: within a tenth of the extended
  // filter's error of it (the two linearise nothing alike: the extended
  // one differences the step, the unscented one spreads points through it).
  const fs::path unscented = dir / "unscented.csv";
  r = run_cli("estimate " + kFourbar + " --filter ukf --measurements " + data.string() + " --out " +
              unscented.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto u = read_columns(unscented);
  for (const char* column : {"z1", "p1", "p2", "p3"})
    EXPECT_LT(rms_difference(u.at(column), e.at(column)),
              0.1 * rms_difference(e.at(column), t.at(column)))
        << column;
}

TEST(EstimateCommand, EstimatesTheValvesFlowCoefficientBesideTheStateFromTheModelsSensors) {
  const fs::path dir = mh::test::scratch_dir("estimate-parameter");
  const fs::path data = dir / "sensors.csv", estimated = dir / "estimated.csv";
  // The machine's valve passes 20 % more than the model's 2.138e-8.
  auto r = run_cli("run " + kFourbar +
                   " --t-end 4 --seed 4 --set subsystems/valve/flow_coefficient=2.5656e-8"
                   " --sensors-out " +
                   data.string() + " --out " + (dir / "truth.csv").string());
  ASSERT_EQ(r.code, 0) << r.output;
  r = run_cli("estimate " + kFourbar +
              " --estimate-params subsystems/valve/flow_coefficient --measurements " +
              data.string() + " --out " + estimated.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto e = read_columns(estimated);
  const double value = e.at("subsystems/valve/flow_coefficient").back();
  const double sd = e.at("subsystems/valve/flow_coefficient_sd").back();
  EXPECT_LT(std::abs(value - 2.5656e-8), 0.01 * 2.5656e-8) << value << " +- " << sd;
  EXPECT_LT(std::abs(value - 2.5656e-8), 3.0 * sd) << value << " +- " << sd;
  // Where it started: the model's value, a fifth of it uncertain.
  EXPECT_DOUBLE_EQ(e.at("subsystems/valve/flow_coefficient").front(), 2.138e-8);
}

TEST(EstimateCommand, BadInputIsRefusedNamingTheFileColumnOrStateAndNoRowIsWritten) {
  const fs::path dir = mh::test::scratch_dir("estimate-bad");
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  };
  const std::string good = write("good.csv", "t,z1\n0,0\n0.001,0\n");
  struct Case {
    std::string args, expected;
  };
  const std::vector<Case> cases = {
      {"--measurements " + write("other.csv", "t,torque\n0,1\n0.1,1\n"),
       "column 'torque' is not one of the model's sensors (z1, p1, p2, p3)"},
      {"--measurements " + write("order.csv", "t,z1\n0,0\n0.2,0\n0.1,0\n"),
       "order.csv:4:1: t: a time after"},
      {"--measurements " + write("nan.csv", "t,z1\n0,0\n0.1,NaN\n"), "nan.csv:3:2: z1"},
      {"--measurements " + write("same.csv", "t,z1\n0,0\n0.0012,0\n0.0014,0\n"),
       "the rows at t = 0.0012 and t = 0.0014 fall on the same step"},
      {"--measurements " + good + " --plant-noise z9=1", "'z9' is not a state of the filter"},
      {"--measurements " + good + " --plant-noise p2=-1",
       "--plant-noise p2=-1: expected a standard deviation of 0 or more"},
      {"--measurements " + good + " --filter pf", "--filter pf: expected ekf or ukf"},
      {"--measurements " + good + " --estimate-params bodies/nobody/mass",
       "--estimate-params: bodies/nobody/mass"},
      {"--measurements " + good + " --estimate-params bodies/body1/z0",
       "bodies/body1/z0: an initial coordinate acts through the start alone"},
      {"--measurements " + write("start.csv", "t,z1\n0,0\n"), "its last sample is at the start"},
      {"--measurements " + good + " --truth " + good, "--truth is what --report compares"},
      {"--measurements " + good + " --filter ekf,ukf",
       "one filter, or a list of them with --report"},
      {"--measurements - --report " + (dir / "r").string(),
       "--report takes the data of a file, not a stream"},
      {"--measurements " + good + " --report " + (dir / "r").string() + " --truth " +
           write("no-state.csv", "t,torque\n0,1\n0.001,1\n"),
       "no-state.csv: no column is a state of the filter (z3, z3_dot, p1, p2, p3, U)"},
  };
  for (const Case& c : cases) {
    const fs::path out = dir / "out.csv";
    fs::remove(out);
    const auto r = run_cli("estimate " + kFourbar + " " + c.args + " --out " + out.string());
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(out)) << c.args;
  }
}

// The data file's rows as a live stream's lines: t,NAME=VALUE for each
// sample taken (a row's empty fields left out).
std::string as_lines(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) header.push_back(cell);
  std::string out;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string cell;
    std::getline(ss, cell, ',');
    out += cell;
    for (size_t c = 1; c < header.size() && std::getline(ss, cell, ','); ++c)
      if (!cell.empty()) out += "," + header[c] + "=" + cell;
    out += "\n";
  }
  return out;
}

// The machine's sensor readings over its first `t_end` s (noise seed 4),
// in DIR/data.csv.
fs::path machine_readings(const fs::path& dir, double t_end) {
  const fs::path data = dir / "data.csv";
  const auto r = run_cli("run " + kFourbar + kMachine + " --t-end " + std::to_string(t_end) +
                         " --seed 4 --sensors-out " + data.string() + " --out " +
                         (dir / "truth.csv").string());
  EXPECT_EQ(r.code, 0) << r.output;
  return data;
}

// The report's cell `column` (from 0) after the cell naming the row `row`.
double report_cell(const std::string& html, const std::string& row, int column) {
  size_t at = html.find("<tr><td>" + row + "</td>");
  if (at == std::string::npos) return NAN;
  for (int c = 0; c <= column + 1; ++c) at = html.find("<td>", at + 1);  // past the row's name
  const size_t end = html.find("</td>", at);
  try {
    return std::stod(html.substr(at + 4, end - at - 4));
  } catch (const std::exception&) {
    return NAN;
  }
}

// --report with both filters and the machine's own run as the truth: the
// report's RMS errors are those of the estimates' CSV against the truth's
// (computed here again), its CSV is the one written without --report, and
// the extended filter's crank within a twentieth of the open loop's error
// and its pressures within 0.3 (the pressure transducers at 100 Hz over
// 2 s); the normalised estimation error is inside its band most steps.
TEST(EstimateCommand, TheReportSetsBothFiltersBesideTheOpenLoopAgainstTheTruth) {
  const fs::path dir = mh::test::scratch_dir("estimate-report");
  const fs::path data = machine_readings(dir, 2.0);
  const fs::path truth = dir / "truth.csv", est = dir / "est.csv", plain = dir / "plain.csv";
  const auto r = run_cli("estimate " + kFourbar + " --measurements " + data.string() +
                         " --filter ekf,ukf --report " + (dir / "report").string() + " --truth " +
                         truth.string() + " --out " + est.string());
  ASSERT_EQ(r.code, 0) << r.output;
  ASSERT_EQ(run_cli("estimate " + kFourbar + " --measurements " + data.string() + " --out " +
                    plain.string())
                .code,
            0);
  std::ifstream a(est), b(plain), h(dir / "report" / "report.html");
  std::stringstream est_text, plain_text, html_text;
  est_text << a.rdbuf();
  plain_text << b.rdbuf();
  html_text << h.rdbuf();
  EXPECT_EQ(est_text.str(), plain_text.str());
  const std::string html = html_text.str();
  const auto e = read_columns(est), t = read_columns(truth);
  ASSERT_EQ(e.at("t").size(), t.at("t").size());
  for (const std::string name : {"z3", "p1", "p2", "p3"}) {
    const std::string row = name + (name == "z3" ? " (rad)" : " (Pa)");
    // Columns: the open loop's RMS, then the extended filter's RMS, its ratio.
    const double ekf = report_cell(html, row, 1), ratio = report_cell(html, row, 2);
    EXPECT_NEAR(ekf, rms_difference(e.at(name), t.at(name)), 1e-5 * ekf) << name;
    EXPECT_LT(ratio, name == "z3" ? 0.05 : 0.3) << name;  // measured: 0.004, 0.22
    EXPECT_LT(report_cell(html, row, 4), 1.2 * ekf) << name << ": the unscented filter's";
  }
  for (const std::string filter : {"ekf", "ukf"})
    EXPECT_GT(report_cell(html, filter, 0), 50.0) << filter << ": NEES inside its band (%)";
  EXPECT_NE(html.find("<h2>The sensors"), std::string::npos);
}

// Pressure transducers 5 ms late (delay: 0.005 on the model's three
// pressure sensors): the filter that knows it corrects the step each
// reading is of and tracks the machine's pressures closer than the same
// data taken as if on time.
TEST(EstimateCommand, DelayedSensorsAreTakenAtTheStepTheyReadNotWhenTheyArrive) {
  const fs::path dir = mh::test::scratch_dir("estimate-delay");
  std::ifstream in(kFourbar);
  std::stringstream text;
  text << in.rdbuf();
  std::string delayed = text.str();
  for (const std::string p : {"p1", "p2", "p3"}) {
    const std::string from = "{name: " + p + ", measures: " + p + ", noise: 3.8e4, rate: 100}";
    const size_t at = delayed.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    delayed.replace(
        at, from.size(),
        "{name: " + p + ", measures: " + p + ", noise: 3.8e4, rate: 100, delay: 0.005}");
  }
  const fs::path late_model = dir / "fourbar-late.yaml", data = dir / "data.csv",
                 truth = dir / "truth.csv";
  std::ofstream(late_model) << delayed;
  ASSERT_EQ(run_cli("run " + late_model.string() + kMachine + " --t-end 4 --seed 3 --sensors-out " +
                    data.string() + " --out " + truth.string())
                .code,
            0);
  const auto rms_of = [&](const std::string& model, const std::string& name) {
    const fs::path out = dir / (name + ".csv");
    const auto r = run_cli("estimate " + model + " --measurements " + data.string() + " --out " +
                           out.string());
    EXPECT_EQ(r.code, 0) << r.output;
    const auto e = read_columns(out), t = read_columns(truth);
    return rms_difference(e.at("p2"), t.at("p2"));
  };
  const double knowing = rms_of(late_model.string(), "knowing");
  const double ignoring = rms_of(kFourbar, "ignoring");  // the same sensors, on time
  EXPECT_LT(knowing, 0.7 * ignoring) << knowing << " Pa against " << ignoring << " Pa";
}

TEST(EstimateCommand, AStreamOfTheFilesRowsGivesTheFilesEstimatesToTheByte) {
  const fs::path dir = mh::test::scratch_dir("estimate-stream");
  const fs::path data = machine_readings(dir, 0.5);
  std::ofstream(dir / "lines.txt") << "# the four-bar's sensors\n\n" << as_lines(data);
  auto r = run_cli("estimate " + kFourbar + " --measurements " + data.string() + " --out " +
                   (dir / "file.csv").string());
  ASSERT_EQ(r.code, 0) << r.output;
  r = run_cli("estimate " + kFourbar + " --measurements - --out " + (dir / "stream.csv").string() +
              " < " + (dir / "lines.txt").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string file = mh::test::read_text(dir / "file.csv");
  EXPECT_EQ(std::count(file.begin(), file.end(), '\n'), 502);  // the header, 0 .. 0.5 s
  EXPECT_EQ(mh::test::read_text(dir / "stream.csv"), file);
}

// Paced to the wall clock, the filter computes what it computes unpaced:
// the same bytes, and how many steps' estimates came after their time.
TEST(EstimateCommand, RealTimeGivesTheUnpacedEstimatesAndCountsTheDeadlinesItMissed) {
  const fs::path dir = mh::test::scratch_dir("estimate-real-time");
  const fs::path data = machine_readings(dir, 0.3);
  auto r = run_cli("estimate " + kFourbar + " --measurements " + data.string() + " --out " +
                   (dir / "unpaced.csv").string());
  ASSERT_EQ(r.code, 0) << r.output;
  r = run_cli("estimate " + kFourbar + " --measurements " + data.string() + " --real-time --out " +
              (dir / "paced.csv").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(mh::test::read_text(dir / "paced.csv"), mh::test::read_text(dir / "unpaced.csv"));
  EXPECT_NE(r.output.find("real time: deadlines missed: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" of 301 steps ("), std::string::npos) << r.output;
  // A stream given all at once: every line early, none late, each taken at
  // its own step; the steps paced from the first line on.
  std::ofstream(dir / "lines.txt") << as_lines(data);
  r = run_cli("estimate " + kFourbar + " --measurements - --real-time --out " +
              (dir / "stream.csv").string() + " < " + (dir / "lines.txt").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("lines taken after their step: 0"), std::string::npos) << r.output;
  EXPECT_EQ(mh::test::read_text(dir / "stream.csv"), mh::test::read_text(dir / "unpaced.csv"));
}

// A bad line stops the stream's filter with the line's number and what was
// expected; the rows before it are written (exit 1).
TEST(EstimateCommand, AStreamsBadLineStopsItNamingTheLineAndKeepsTheRowsBefore) {
  const fs::path dir = mh::test::scratch_dir("estimate-stream-bad");
  struct Case {
    std::string tail, expected;
    long rows = 3;  // the header and the steps at 0 and 1 ms
  };
  const std::vector<Case> cases = {
      {"0.002,z1=0\n0.001,z1=0\n", "standard input:4: t: times that do not go backwards", 4},
      {"0.0021,z1=0\n0.0022,z1=0\n", "standard input:4: t: one line per step of 0.001 s", 4},
      {"0.002,torque=1\n", "standard input:3: torque: one of the model's sensors (z1, p1, p2, p3)"},
      {"0.002,z1=high\n", "standard input:3: z1: a finite number, not 'high'"},
      {"0.002,z1=nan\n", "standard input:3: z1: a finite number, not 'nan'"},
      {"0.002,z1\n", "standard input:3: field 2: NAME=VALUE, not 'z1'"},
      {"0.002,z1=0,z1=1\n", "standard input:3: z1: one reading per sensor and line"},
      {"soon,z1=0\n", "standard input:3: t: a time in s first"},
  };
  for (const Case& c : cases) {
    std::ofstream(dir / "lines.txt") << "0,z1=0\n0.001,z1=1e-5,p1=\n" << c.tail;
    const fs::path out = dir / "out.csv";
    const auto r = run_cli("estimate " + kFourbar + " --measurements - --out " + out.string() +
                           " < " + (dir / "lines.txt").string());
    EXPECT_EQ(r.code, 1) << c.tail << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.tail << r.output;
    // The header and the rows of the steps before the bad line.
    const std::string rows = mh::test::read_text(out);
    EXPECT_EQ(std::count(rows.begin(), rows.end(), '\n'), c.rows) << c.tail << rows;
  }
  // A first line before the run's start: nothing but the header written.
  for (const char* paced : {"", " --real-time"}) {
    std::ofstream(dir / "early.txt") << "-0.002,z1=0\n0,z1=0\n";
    const fs::path out = dir / "early.csv";
    const auto r = run_cli("estimate " + kFourbar + " --measurements -" + paced + " --out " +
                           out.string() + " < " + (dir / "early.txt").string());
    EXPECT_EQ(r.code, 1) << paced << r.output;
    EXPECT_NE(r.output.find("standard input:1: t: a time at or after the run's start (0 s), "
                            "not -0.002"),
              std::string::npos)
        << paced << r.output;
    const std::string rows = mh::test::read_text(out);
    EXPECT_EQ(std::count(rows.begin(), rows.end(), '\n'), 1) << paced << rows;
  }
}

}  // namespace
