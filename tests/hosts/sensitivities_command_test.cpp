// monohydra sensitivities (hosts/monohydra/sensitivities_command.cpp) as a
// user runs it: a column of d(NAME)/d(PATH) for every coordinate, named
// state and output and every parameter, which agrees with the difference of
// two `run --set` CSVs; and bad parameters refused, naming them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "build_paths.hpp"
#include "cli_runner.hpp"

namespace {

using mh::test::CliResult;
using mh::test::run_cli;

std::string model(const std::string& name) {
  return mh::test::shipped_model(name);
}

struct Table {
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;
  size_t column(const std::string& name) const {
    return static_cast<size_t>(std::find(names.begin(), names.end(), name) - names.begin());
  }
};

Table read_csv(const std::filesystem::path& path) {
  Table t;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::stringstream header(line);
  for (std::string name; std::getline(header, name, ',');) t.names.push_back(name);
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::vector<double> values;
    for (std::string v; std::getline(row, v, ',');) values.push_back(std::stod(v));
    t.rows.push_back(values);
  }
  return t;
}

// The four-bar with Newton converged to round-off, so that whole runs
// difference cleanly.
std::string tight_fourbar(const std::filesystem::path& dir) {
  std::ifstream in(model("fourbar.yaml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  const std::string from = "tol_position: 1e-7}";
  const size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos);
  s.replace(at, from.size(), "tol_position: 1e-11, newton: full}");
  const auto path = dir / "fourbar-tight.yaml";
  std::ofstream(path) << s;
  return path.string();
}

TEST(SensitivitiesCommand, ColumnsAgreeWithTheDifferenceOfTwoRunsWithTheValueSet) {
  const auto dir =
      std::filesystem::path(mh::test::paths::binary_dir) / "test-scratch" / "sensitivities";
  std::filesystem::create_directories(dir);
  const std::string fourbar = tight_fourbar(dir);
  const CliResult s = run_cli("sensitivities " + fourbar +
                              " --params bodies/body3/mass,gravity/1 --t-end 2 --out " +
                              (dir / "sens.csv").string());
  ASSERT_EQ(s.code, 0) << s.output;
  const double delta = 5e-4;  // kg
  for (const auto& [name, mass] : {std::pair<std::string, double>{"plus", 50.0 + delta},
                                   std::pair<std::string, double>{"minus", 50.0 - delta}}) {
    std::ostringstream value;
    value.precision(17);
    value << mass;
    const CliResult r =
        run_cli("run " + fourbar + " --t-end 2 --set bodies/body3/mass=" + value.str() + " --out " +
                (dir / (name + ".csv")).string());
    ASSERT_EQ(r.code, 0) << r.output;
  }
  const Table sens = read_csv(dir / "sens.csv");
  const Table plus = read_csv(dir / "plus.csv");
  const Table minus = read_csv(dir / "minus.csv");
  ASSERT_EQ(sens.rows.size(), plus.rows.size());
  EXPECT_LT(sens.column("d(p2)/d(gravity/1)"), sens.names.size());
  for (const std::string name : {"z1", "p1", "p3", "Fs"}) {
    const size_t c = sens.column("d(" + name + ")/d(bodies/body3/mass)");
    const size_t v = plus.column(name);
    ASSERT_LT(c, sens.names.size()) << name;
    ASSERT_LT(v, plus.names.size()) << name;
    double largest = 0.0;
    for (const auto& row : sens.rows) largest = std::max(largest, std::abs(row[c]));
    ASSERT_GT(largest, 0.0) << name;
    // The CSVs' 10 significant digits bound the agreement.
    for (size_t k = 0; k < sens.rows.size(); k += 100) {
      const double differenced = (plus.rows[k][v] - minus.rows[k][v]) / (2.0 * delta);
      EXPECT_NEAR(sens.rows[k][c], differenced, 1e-3 * largest)
          << name << " at t = " << sens.rows[k][0];
    }
  }
}

TEST(SensitivitiesCommand, RefusesParametersItCannotTakeNamingThem) {
  const CliResult option = run_cli("sensitivities " + model("fourbar.yaml") +
                                   " --params subsystems/cylinder/length --t-end 0.01");
  EXPECT_EQ(option.code, 2);
  EXPECT_NE(option.output.find("subsystems/cylinder/length: subsystem 'cylinder' (cylinder) does "
                               "not change 'length' in place (its parameters: piston_diameter, "),
            std::string::npos)
      << option.output;
  const CliResult fixed = run_cli("sensitivities " + model("excavator.yaml") +
                                  " --params subsystems/relief/cracking_pressure --t-end 0.01");
  EXPECT_EQ(fixed.code, 2);
  EXPECT_NE(fixed.output.find("subsystem 'relief' (relief-valve) changes none of its options in "
                              "place"),
            std::string::npos)
      << fixed.output;
  const CliResult missing =
      run_cli("sensitivities " + model("fourbar.yaml") + " --params bodies/boom/mass");
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.output.find("no item named 'boom' in bodies"), std::string::npos)
      << missing.output;
  const CliResult none = run_cli("sensitivities " + model("fourbar.yaml"));
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.output.find("needs --params"), std::string::npos) << none.output;
}

}  // namespace
