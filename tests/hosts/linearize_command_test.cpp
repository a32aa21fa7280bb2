// monohydra linearize (hosts/monohydra/linearize_command.cpp) as a user runs
// it: its YAML parses, its matrices have the sizes of its names, its
// eigenvalues are A's, and bad arguments are usage errors that name them.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <algorithm>
#include <complex>
#include <filesystem>
#include <string>
#include <vector>

#include "build_paths.hpp"
#include "cli_runner.hpp"
#include "monohydra/core/linearization.hpp"

namespace {

using mh::eigenvalues;
using mh::test::CliResult;
using mh::test::run_cli;

std::string model(const std::string& name) {
  return mh::test::shipped_model(name);
}

Eigen::MatrixXd matrix(const YAML::Node& rows, size_t cols) {
  Eigen::MatrixXd m(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols));
  for (size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].size(), cols) << "row " << i;
    for (size_t j = 0; j < cols && j < rows[i].size(); ++j)
      m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = rows[i][j].as<double>();
  }
  return m;
}

TEST(LinearizeCommand, WritesYamlWhoseMatricesHaveTheSizesOfTheirNames) {
  const auto dir =
      std::filesystem::path(mh::test::paths::binary_dir) / "test-scratch" / "linearize";
  std::filesystem::create_directories(dir);
  const std::string out = (dir / "fourbar.yaml").string();
  std::filesystem::remove(out);
  const CliResult r = run_cli("linearize " + model("fourbar.yaml") +
                              " --at 0.5 --outputs s,z1_dot,U --formulation penalty --out " + out);
  ASSERT_EQ(r.code, 0) << r.output;
  const YAML::Node doc = YAML::LoadFile(out);
  EXPECT_EQ(doc["formulation"].as<std::string>(), "penalty");
  EXPECT_NEAR(doc["t"].as<double>(), 0.5, 1e-12);
  const size_t n = doc["states"].size(), m = doc["inputs"].size(), p = doc["outputs"].size();
  EXPECT_EQ(n, 10u);  // z1..z3, their rates, p1..p3, U
  ASSERT_EQ(m, 1u);
  EXPECT_EQ(doc["inputs"][0]["name"].as<std::string>(), "valve_command");
  ASSERT_EQ(p, 3u);
  EXPECT_EQ(doc["outputs"][1]["name"].as<std::string>(), "z1_dot");
  EXPECT_EQ(doc["outputs"][1]["unit"].as<std::string>(), "rad/s");
  const Eigen::MatrixXd A = matrix(doc["A"], n), B = matrix(doc["B"], m);
  const Eigen::MatrixXd C = matrix(doc["C"], n), D = matrix(doc["D"], m);
  EXPECT_EQ(A.rows(), static_cast<Eigen::Index>(n));
  EXPECT_EQ(B.rows(), static_cast<Eigen::Index>(n));
  EXPECT_EQ(C.rows(), static_cast<Eigen::Index>(p));
  EXPECT_EQ(D.rows(), static_cast<Eigen::Index>(p));
  // The listed eigenvalues are those of the A written (to the bit, so within
  // round-off), as the library computes them (balanced: an unbalanced QR
  // iteration misses the slow ones by 1e-5 1/s on this matrix).
  const std::vector<std::complex<double>> ours = eigenvalues(A);
  ASSERT_EQ(doc["eigenvalues"].size(), n);
  for (const YAML::Node& e : doc["eigenvalues"]) {
    const std::complex<double> v(e["re"].as<double>(), e["im"].as<double>());
    double nearest = 1e300;
    for (const auto& o : ours) nearest = std::min(nearest, std::abs(o - v));
    EXPECT_LT(nearest, 1e-9 * std::max(1.0, std::abs(v))) << v;
    if (v.imag() == 0.0 && v.real() < 0.0)
      EXPECT_NEAR(e["time_constant"].as<double>(), -1.0 / v.real(), 1e-12 / -v.real());
    else
      EXPECT_TRUE(e["time_constant"].IsNull());
  }
}

TEST(LinearizeCommand, PrintsToStdoutAtTheInitialStateByDefault) {
  const CliResult r = run_cli("linearize " + model("fourbar.yaml") + " --outputs p1 2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.output;
  const YAML::Node doc = YAML::Load(r.output);
  EXPECT_EQ(doc["t"].as<double>(), 0.0);
  EXPECT_EQ(doc["states"].size(), 6u);  // double-step: z3, z3_dot, p1..p3, U
  EXPECT_EQ(doc["outputs"][0]["unit"].as<std::string>(), "Pa");
}

TEST(LinearizeCommand, BadArgumentsAreUsageErrorsThatNameThem) {
  const CliResult bad = run_cli("linearize " + model("fourbar.yaml") + " --outputs s,no_such");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("unknown output 'no_such'"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("z1_dot"), std::string::npos) << bad.output;  // what there is
  const CliResult at = run_cli("linearize " + model("fourbar.yaml") + " --at soon");
  EXPECT_EQ(at.code, 2) << at.output;
  EXPECT_NE(at.output.find("--at"), std::string::npos) << at.output;
  const CliResult none = run_cli("linearize");
  EXPECT_EQ(none.code, 2) << none.output;
  const CliResult formulation =
      run_cli("linearize " + model("fourbar.yaml") + " --formulation no-such-formulation");
  EXPECT_NE(formulation.code, 0) << formulation.output;
}

}  // namespace
