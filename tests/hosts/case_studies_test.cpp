// The paper's case studies as data (models/paper-reference.yaml, read by
// hosts/monohydra/case_studies.cpp): the numbers are the last table of
// ../shared/case-studies.md, and mistakes in the file are named.
#include "case_studies.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "build_paths.hpp"
#include "monohydra/core/input_error.hpp"
#include "test_support.hpp"

namespace mh::test {
namespace {

namespace fs = std::filesystem;

TEST(CaseStudies, TheShippedFileHoldsThePapersNumbers) {
  const auto studies = cli::load_case_studies(source_path("models/paper-reference.yaml"));
  ASSERT_EQ(studies.size(), 2u);
  const cli::CaseStudy& fb = studies[0];
  const cli::CaseStudy& qr = studies[1];
  EXPECT_EQ(fb.name, "four-bar");
  EXPECT_EQ(fs::path(fb.model_path).filename(), "fourbar.yaml");
  EXPECT_EQ(fb.report_dir, "out/fourbar");
  EXPECT_EQ(fb.formulations, (std::vector<std::string>{"double-step", "penalty"}));
  EXPECT_EQ(fb.paper.integrator, "trapezoidal");
  // The paper's Newton-Raphson factors a tangent at every iteration (Eq. 37).
  EXPECT_EQ(fb.newton, NewtonKind::full);
  EXPECT_EQ(qr.newton, NewtonKind::full);
  EXPECT_EQ(fb.paper.run("double-step", "trapezoidal")->coordinates, "z3 throughout");
  EXPECT_EQ(fb.paper.run("double-step", "bdf2"), nullptr);  // the paper ran trapezoidal only
  EXPECT_EQ(*fb.paper.max_actuator_work, 982.95);
  EXPECT_EQ(*fb.paper.peak_drift, 0.84);
  EXPECT_EQ(*fb.paper.peak_drift_percent, 0.09);
  ASSERT_NE(fb.paper.run("double-step", "trapezoidal"), nullptr);
  EXPECT_EQ(*fb.paper.run("double-step", "trapezoidal")->avg_iterations, 1.39);
  EXPECT_EQ(*fb.paper.run("double-step", "trapezoidal")->max_iterations, 3.0);
  EXPECT_EQ(*fb.paper.run("double-step", "trapezoidal")->total_seconds, 27.45);
  EXPECT_EQ(*fb.paper.run("penalty", "trapezoidal")->avg_iterations, 1.56);
  EXPECT_EQ(*fb.paper.run("penalty", "trapezoidal")->max_iterations, 4.0);
  EXPECT_EQ(*fb.paper.run("penalty", "trapezoidal")->total_seconds, 21.54);

  EXPECT_EQ(qr.name, "quick-return");
  EXPECT_EQ(fs::path(qr.model_path).filename(), "quickreturn.yaml");
  EXPECT_EQ(qr.paper.run("double-step", "trapezoidal")->coordinates, "z4 throughout");
  EXPECT_EQ(*qr.paper.max_actuator_work, 357.47);
  EXPECT_EQ(*qr.paper.peak_drift, 0.23);
  EXPECT_EQ(*qr.paper.peak_drift_percent, 0.06);
  EXPECT_EQ(*qr.paper.run("double-step", "trapezoidal")->avg_iterations, 1.49);
  EXPECT_EQ(*qr.paper.run("double-step", "trapezoidal")->max_iterations, 3.0);
  EXPECT_EQ(*qr.paper.run("double-step", "trapezoidal")->total_seconds, 29.03);
  EXPECT_EQ(*qr.paper.run("penalty", "trapezoidal")->avg_iterations, 1.57);
  EXPECT_EQ(*qr.paper.run("penalty", "trapezoidal")->max_iterations, 6.0);
  EXPECT_EQ(*qr.paper.run("penalty", "trapezoidal")->total_seconds, 28.47);
  EXPECT_EQ(qr.paper.run("open-loop", "trapezoidal"), nullptr);
  // The paper's colours for the open valve: purple, then cyan.
  EXPECT_NE(fb.control_shading, qr.control_shading);
}

fs::path write(const std::string& name, const std::string& text) {
  const fs::path p = fs::path(mh::test::paths::binary_dir) / "case_studies_test" / name;
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
  return p;
}

TEST(CaseStudies, ModelPathsAreRelativeToTheFile) {
  const fs::path p = write("relative.yaml",
                           "case_studies:\n"
                           "  - {name: a, model: sub/a.yaml, report: out/a, formulations: [x]}\n");
  const auto studies = cli::load_case_studies(p.string());
  EXPECT_EQ(studies[0].model_path, (p.parent_path() / "sub" / "a.yaml").string());
  EXPECT_TRUE(studies[0].paper.runs.empty());
}

TEST(CaseStudies, MistakesNameTheFileLineAndField) {
  const fs::path typo = write("typo.yaml",
                              "case_studies:\n"
                              "  - name: a\n"
                              "    model: a.yaml\n"
                              "    report: out/a\n"
                              "    formulations: [x]\n"
                              "    paper: {max_actuator_wrok: 1}\n");
  try {
    cli::load_case_studies(typo.string());
    FAIL() << "no error";
  } catch (const InputError& err) {
    const std::string what = err.what();
    EXPECT_EQ(what.rfind(typo.string() + ":6:", 0), 0u) << what;
    EXPECT_NE(what.find("case_studies[0].paper.max_actuator_wrok: unknown key"), std::string::npos)
        << what;
  }
  const fs::path text = write("text.yaml",
                              "case_studies:\n"
                              "  - {name: a, model: a.yaml, report: r, formulations: [x],\n"
                              "     paper: {peak_drift: \"0.84\"}}\n");
  EXPECT_THROW(cli::load_case_studies(text.string()), InputError);
  EXPECT_THROW(cli::load_case_studies("/no/such/file.yaml"), InputError);
  const fs::path newton = write("newton.yaml",
                                "case_studies:\n"
                                "  - {name: a, model: a.yaml, report: r, formulations: [x],\n"
                                "     newton: quasi}\n");
  try {
    cli::load_case_studies(newton.string());
    FAIL() << "no error";
  } catch (const InputError& err) {
    const std::string what = err.what();
    EXPECT_EQ(what.rfind(newton.string() + ":3:", 0), 0u) << what;
    EXPECT_NE(
        what.find("case_studies[0].newton: expected auto, full, per-step, modified or articulated"),
        std::string::npos)
        << what;
  }
}

TEST(CaseStudies, AModelIsFoundByItsFileNotItsSpelling) {
  const fs::path model = write("m.yaml", "units: {}\n");
  const fs::path p = write("find.yaml",
                           "case_studies:\n"
                           "  - {name: a, model: m.yaml, report: r, formulations: [x]}\n");
  const auto studies = cli::load_case_studies(p.string());
  const std::string other_spelling = (model.parent_path() / "." / "m.yaml").string();
  EXPECT_EQ(cli::find_case_study(studies, other_spelling), &studies[0]);
  EXPECT_EQ(cli::find_case_study(studies, p.string()), nullptr);
}

}  // namespace
}  // namespace mh::test
