// The analytic tangent end to end (core/src/step/subsystem_coupling.cpp with the
// formulations' tangent and mechanics_map): the whole assembled
// Newton tangent of runs whose subsystems act at body points (the hydraulic
// cylinder of the case studies, the Maxwell element) equals central
// differences of the residual in every entry, and assembling it differences
// no residual at all.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

// max |J - J_ref| over each row, relative to that row's largest |J_ref| (the
// rows have the scales of forces, penalties and flows).
double worst_row_error(const Eigen::MatrixXd& J, const Eigen::MatrixXd& J_ref, int* row) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < J.rows(); ++i) {
    const double scale = std::max(J_ref.row(i).cwiseAbs().maxCoeff(), 1e-12);
    const double e = (J.row(i) - J_ref.row(i)).cwiseAbs().maxCoeff() / scale;
    if (e > worst) {
      worst = e;
      *row = static_cast<int>(i);
    }
  }
  return worst;
}

struct Case {
  const char* model;
  const char* formulation;
  double t;  // the tangent is taken at the first step after t
};

class AnalyticTangent : public ::testing::TestWithParam<Case> {};

TEST_P(AnalyticTangent, EqualsCentralDifferencesInEveryEntry) {
  const Case c = GetParam();
  const ModelFile file = load_model_file(test::source_path(std::string("models/") + c.model));
  Simulation sim(file, test::build_plugins(), RunChoices{c.formulation, "", {}, {}});
  sim.start();
  const long steps = std::lround(c.t / sim.settings().dt);
  for (long k = 0; k < steps; ++k) sim.step();
  const Eigen::MatrixXd J = sim.assembled_tangent();
  const Eigen::MatrixXd J_cd = sim.central_difference_tangent();
  const int nm = sim.num_mechanical_unknowns();
  const int ns = sim.num_unknowns() - nm;
  // The mechanical rows (every column) and the state rows' mechanical columns;
  // the state-state block is the plugins' own jacobian, tested with them.
  int row = -1;
  double err = worst_row_error(J.topRows(nm), J_cd.topRows(nm), &row);
  EXPECT_LT(err, 1e-5) << c.model << " / " << c.formulation << ": mechanical row " << row
                       << "\nanalytic\n"
                       << J.row(row) << "\ncentral\n"
                       << J_cd.row(row);
  err = worst_row_error(J.bottomLeftCorner(ns, nm), J_cd.bottomLeftCorner(ns, nm), &row);
  EXPECT_LT(err, 1e-5) << c.model << " / " << c.formulation << ": state row " << row
                       << "\nanalytic\n"
                       << J.bottomLeftCorner(ns, nm).row(row) << "\ncentral\n"
                       << J_cd.bottomLeftCorner(ns, nm).row(row);
  // The coupling is there: some mechanical row depends on a state and some
  // state row on a mechanical unknown.
  EXPECT_GT(J.topRightCorner(nm, ns).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GT(J.bottomLeftCorner(ns, nm).cwiseAbs().maxCoeff(), 0.0);
}

INSTANTIATE_TEST_SUITE_P(CaseStudiesAndMaxwell, AnalyticTangent,
                         ::testing::Values(Case{"fourbar.yaml", "penalty", 1.5},
                                           Case{"fourbar.yaml", "penalty", 6.0},
                                           Case{"quickreturn.yaml", "penalty", 1.5},
                                           Case{"quickreturn.yaml", "penalty", 6.0},
                                           Case{"maxwell-pendulum.yaml", "open-loop", 0.3}),
                         [](const ::testing::TestParamInfo<Case>& p) {
                           std::string name = std::string(p.param.model) + "_" +
                                              p.param.formulation + "_" +
                                              std::to_string(static_cast<int>(p.param.t * 10));
                           std::replace_if(
                               name.begin(), name.end(),
                               [](char ch) { return std::isalnum(ch) == 0; }, '_');
                           return name;
                         });

TEST(AnalyticTangent, AssemblingItDifferencesNoResidual) {
  const ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  Simulation sim(file, test::build_plugins(), RunChoices{"penalty", "", {}, {}});
  sim.start();
  for (int k = 0; k < 1500; ++k) sim.step();
  const long before = sim.counters().residual_evaluations;
  sim.assembled_tangent();  // one residual at the prediction, then the tangent
  EXPECT_EQ(sim.counters().residual_evaluations - before, 1);
}

TEST(AnalyticTangent, DoubleStepDifferencesNoResidual) {
  // double-step gives its f = 1 mechanical column analytically (tangent, from
  // mech_derivatives and R_z's derivative) and a mechanics_map, so the host
  // couples the pressures analytically and differences nothing.
  const ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  Simulation sim(file, test::build_plugins(), RunChoices{"double-step", "", {}, {}});
  sim.start();
  for (int k = 0; k < 1500; ++k) sim.step();
  const long before = sim.counters().residual_evaluations;
  const Eigen::MatrixXd J = sim.assembled_tangent();
  const int nm = sim.num_mechanical_unknowns();
  EXPECT_EQ(sim.counters().residual_evaluations - before, 1);
  // Its rows (every column analytic) and the state rows' mechanical column
  // agree with central differences.
  const Eigen::MatrixXd J_cd = sim.central_difference_tangent();
  const int ns = sim.num_unknowns() - nm;
  int row = -1;
  EXPECT_LT(worst_row_error(J.topRows(nm), J_cd.topRows(nm), &row), 1e-5) << "row " << row;
  EXPECT_LT(worst_row_error(J.bottomLeftCorner(ns, nm), J_cd.bottomLeftCorner(ns, nm), &row), 1e-5)
      << "state row " << row;
}

// What mechanics_map says of the coordinates (dz/dx, and dzd/dx along the
// integrator's map) agrees with central differences of the coordinates the
// residual passed to evaluate_mechanics: double-step's dependent coordinates
// (R_z, Eq. 14, and the rates' derivative from dA/dzd), penalty's identity.
TEST(AnalyticTangent, MechanicsMapEqualsCentralDifferencesOfTheCoordinates) {
  for (const char* formulation : {"double-step", "penalty"}) {
    for (const char* model : {"fourbar.yaml", "quickreturn.yaml"}) {
      const ModelFile file = load_model_file(test::source_path(std::string("models/") + model));
      Simulation sim(file, test::build_plugins(), RunChoices{formulation, "", {}, {}});
      sim.start();
      for (int k = 0; k < 1500; ++k) sim.step();
      const Simulation::CoordinateMaps maps = sim.coordinate_maps();
      const double scale_z = std::max(maps.dz_dx_cd.cwiseAbs().maxCoeff(), 1e-12);
      const double scale_zd = std::max(maps.dzd_dx_cd.cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_LT((maps.dz_dx - maps.dz_dx_cd).cwiseAbs().maxCoeff() / scale_z, 1e-6)
          << formulation << " " << model << "\n"
          << maps.dz_dx << "\n\n"
          << maps.dz_dx_cd;
      EXPECT_LT((maps.dzd_dx - maps.dzd_dx_cd).cwiseAbs().maxCoeff() / scale_zd, 1e-6)
          << formulation << " " << model << "\n"
          << maps.dzd_dx << "\n\n"
          << maps.dzd_dx_cd;
    }
  }
}

}  // namespace
}  // namespace mh
