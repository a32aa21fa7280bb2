// A study file's cases: factorial and zipped combinations in a fixed order,
// ranges with exact ends, seeded draws that repeat and stay in their
// distribution, and errors that name the study file, line and field.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "case_expansion.hpp"
#include "cli_runner.hpp"

namespace mh::cli::sweep {
namespace {

namespace fs = std::filesystem;

// A study file in a scratch folder beside a copy of the four-bar.
std::string write_study(const std::string& name, const std::string& body) {
  const fs::path dir = mh::test::scratch_dir("sweep-expansion-" + name);
  const std::string model = mh::test::shipped_model("fourbar.yaml");
  std::ofstream(dir / "study.yaml") << "models:\n  - {name: fourbar, file: " << model << "}\n"
                                    << body;
  return (dir / "study.yaml").string();
}

std::vector<double> numbers(const std::vector<YAML::Node>& values) {
  std::vector<double> out;
  for (const auto& v : values) out.push_back(v.as<double>());
  return out;
}

TEST(SweepCaseExpansion, FactorialRunsEveryCombinationWithTheLastParameterFastest) {
  const Study s = load_study(write_study("factorial",
                                         "parameters:\n"
                                         "  formulation/name: [double-step, penalty]\n"
                                         "  solver/dt: [0.001, 0.002, 0.005]\n"));
  const auto cases = expand_cases(s);
  ASSERT_EQ(cases.size(), 6u);
  EXPECT_EQ(cases[0].values[0].second.Scalar(), "double-step");
  EXPECT_EQ(cases[0].values[1].second.Scalar(), "0.001");
  EXPECT_EQ(cases[2].values[1].second.Scalar(), "0.005");
  EXPECT_EQ(cases[3].values[0].second.Scalar(), "penalty");
  EXPECT_EQ(cases[5].index, 5);
  EXPECT_EQ(varied_paths(s), (std::vector<std::string>{"formulation/name", "solver/dt"}));
}

TEST(SweepCaseExpansion, ZipTakesTheIthValuesTogetherAndRefusesUnequalLengths) {
  const Study s = load_study(write_study("zip",
                                         "combine: zip\nparameters:\n"
                                         "  solver/dt: [0.001, 0.002]\n"
                                         "  solver/t_end: [1, 2]\n"));
  const auto cases = expand_cases(s);
  ASSERT_EQ(cases.size(), 2u);
  EXPECT_EQ(cases[1].values[0].second.Scalar(), "0.002");
  EXPECT_EQ(cases[1].values[1].second.Scalar(), "2");
  const Study bad = load_study(write_study("zip-bad",
                                           "combine: zip\nparameters:\n"
                                           "  solver/dt: [0.001, 0.002]\n"
                                           "  solver/t_end: [1, 2, 3]\n"));
  try {
    expand_cases(bad);
    FAIL() << "unequal zip lists accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("study.yaml:6:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("expected 2 values, got 3"), std::string::npos);
  }
}

TEST(SweepCaseExpansion, RangesHitTheirEndsExactlyAndLogRangesAreGeometric) {
  const Study s = load_study(write_study("ranges",
                                         "parameters:\n"
                                         "  solver/dt: {from: 0.00025, to: 0.005, count: 5, "
                                         "scale: log}\n"
                                         "  solver/t_end: {from: 1, to: 2, step: 0.25}\n"));
  const auto dt = numbers(parameter_values(s, 0));
  ASSERT_EQ(dt.size(), 5u);
  EXPECT_EQ(dt.front(), 0.00025);
  EXPECT_EQ(dt.back(), 0.005);
  for (std::size_t i = 1; i + 1 < dt.size(); ++i)
    EXPECT_NEAR(dt[i] / dt[i - 1], dt[i + 1] / dt[i], 1e-12);
  EXPECT_EQ(numbers(parameter_values(s, 1)), (std::vector<double>{1, 1.25, 1.5, 1.75, 2}));
}

TEST(SweepCaseExpansion, SeededDrawsRepeatAndFollowTheirDistribution) {
  const std::string body =
      "parameters:\n"
      "  subsystems/valve/flow_coefficient: {distribution: uniform, low: 1e-8, high: 3e-8, "
      "count: 2000}\n"
      "  subsystems/pump/pressure: {distribution: normal, mean: 7.6e6, std: 1e5, count: 2000}\n"
      "combine: zip\n";
  const Study a = load_study(write_study("draw-a", "seed: 7\n" + body));
  const Study b = load_study(write_study("draw-b", "seed: 7\n" + body));
  const Study c = load_study(write_study("draw-c", "seed: 8\n" + body));
  const auto ua = numbers(parameter_values(a, 0));
  EXPECT_EQ(ua, numbers(parameter_values(b, 0)));  // same seed: same draws
  EXPECT_NE(ua, numbers(parameter_values(c, 0)));
  double sum = 0.0;
  for (double v : ua) {
    EXPECT_GE(v, 1e-8);
    EXPECT_LT(v, 3e-8);
    sum += v;
  }
  EXPECT_NEAR(sum / 2000.0, 2e-8, 5 * (2e-8 / std::sqrt(3.0)) / std::sqrt(2000.0));
  const auto n = numbers(parameter_values(a, 1));
  double mean = 0.0, var = 0.0;
  for (double v : n) mean += v / 2000.0;
  for (double v : n) var += (v - mean) * (v - mean) / 1999.0;
  EXPECT_NEAR(mean, 7.6e6, 5 * 1e5 / std::sqrt(2000.0));
  EXPECT_NEAR(std::sqrt(var), 1e5, 0.1e5);
  EXPECT_EQ(expand_cases(a).size(), 2000u);
}

TEST(SweepCaseExpansion, APathTheModelDoesNotHaveIsRefusedWithTheStudyFileLine) {
  const std::string path = write_study("bad-path",
                                       "parameters:\n"
                                       "  solver/dt: [0.001]\n"
                                       "  subsystems/valve/flow_coef: [1e-8]\n");
  try {
    load_study(path);
    FAIL() << "a missing path was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path + ":5:3: parameters/subsystems/valve/flow_coef: not a value of "
                               "model fourbar: no 'flow_coef' in subsystems/valve"),
              std::string::npos)
        << what;
  }
}

TEST(SweepCaseExpansion, UnknownMetricsAndReferencesAreRefused) {
  EXPECT_THROW(load_study(write_study("bad-metric", "metrics: [peak_drfit]\n")), InputError);
  try {
    load_study(write_study("bad-ref", "metrics:\n  - {error: z3, reference: fine}\n"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no reference run named 'fine'"), std::string::npos);
  }
}

}  // namespace
}  // namespace mh::cli::sweep
