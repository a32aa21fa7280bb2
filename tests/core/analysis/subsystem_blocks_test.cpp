// A subsystem instance's derivative blocks against differences of its own
// evaluate (core/src/analysis/subsystem_blocks.cpp), and the test hook that
// plants an error in one entry where the host receives it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

// The shipped four-bar as written (the tests step it themselves).
const ModelFile& fourbar() {
  static const ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  return file;
}

const Simulation::DerivativeBlock& named(const std::vector<Simulation::DerivativeBlock>& blocks,
                                         const std::string& name) {
  for (const auto& b : blocks)
    if (b.name == name) return b;
  throw std::out_of_range("no block " + name);
}

// The column-major index of a matrix's largest entry.
Eigen::Index largest_entry(const Eigen::MatrixXd& m) {
  Eigen::Index e = 0;
  Eigen::Map<const Eigen::VectorXd>(m.data(), m.size()).cwiseAbs().maxCoeff(&e);
  return e;
}

// The four-bar's cylinder at 1.5 s (the valve open, the piston moving):
// every block its jacobian, coupling_jacobian and point_force_jacobian give
// is central differences of its own evaluate, entry by entry, to 1e-4 and ten
// times the differences' own error (their distance from those at a ten
// times larger step: the friction's smoothing at 0.01 m/s); the names say
// which row and column.
TEST(SubsystemBlocks, TheCylindersBlocksAreDifferencesOfItsOwnEvaluate) {
  Simulation sim(fourbar(), test::build_plugins(), "double-step");
  sim.start();
  while (sim.time() < 1.5 - 1e-12) sim.step();
  const std::vector<Simulation::DerivativeBlock> blocks = sim.subsystem_blocks("cylinder");
  // Its chambers' compliance (rates), the flows its piston's speed pushes,
  // the force of its pressures, and its axis turning with its points.
  for (const char* name : {"dR/dydot", "dR/dv", "dF/dy", "dF/dp"})
    EXPECT_GT(named(blocks, name).sample.analytic.cwiseAbs().maxCoeff(), 0.0) << name;
  for (const Simulation::DerivativeBlock& b : blocks) {
    const std::string& name = b.name;
    ASSERT_TRUE(b.given) << name;
    ASSERT_EQ(b.rows.size(), static_cast<size_t>(b.sample.analytic.rows())) << name;
    ASSERT_EQ(b.columns.size(), static_cast<size_t>(b.sample.analytic.cols())) << name;
    const Eigen::MatrixXd d = 0.5 * (b.sample.forward + b.sample.backward);
    const double largest = d.cwiseAbs().maxCoeff();
    for (Eigen::Index r = 0; r < d.rows(); ++r)
      for (Eigen::Index c = 0; c < d.cols(); ++c)
        EXPECT_NEAR(b.sample.analytic(r, c), d(r, c),
                    1e-4 * std::abs(d(r, c)) + 1e-9 * largest +
                        10.0 * std::abs(d(r, c) - b.sample.central_coarse(r, c)))
            << name << " row " << b.rows[r] << ", column " << b.columns[c];
  }
  // Rows by the run's state names, columns by point key and axis.
  std::vector<std::string> states;
  for (const auto& v : sim.state_info()) states.push_back(v.qualified);
  const Simulation::DerivativeBlock& dp = named(blocks, "dR/dp");
  for (const std::string& row : dp.rows)
    EXPECT_NE(std::find(states.begin(), states.end(), row), states.end()) << row;
  EXPECT_EQ(dp.columns.front(), "point a x");
  EXPECT_EQ(dp.columns.back(), "point b z");
  EXPECT_EQ(named(blocks, "dF/dy").rows.front(), "force on point a x");
  EXPECT_EQ(named(blocks, "dR/dydot").columns.front(), "rate of " + dp.rows.front());
}

// A planted factor scales exactly the entry named, each time the op's
// result is received, until cleared; an unknown block or instance is
// refused naming what there is.
TEST(SubsystemBlocks, APlantedErrorScalesOneEntryUntilClearedAndUnknownNamesAreRefused) {
  Simulation sim(fourbar(), test::build_plugins(), "double-step");
  sim.start();
  while (sim.time() < 1.5 - 1e-12) sim.step();
  const Eigen::MatrixXd before =
      named(sim.subsystem_blocks("cylinder", false), "dR/dp").sample.analytic;
  Eigen::Index entry = largest_entry(before);
  sim.plant_derivative_error("cylinder", "dR/dp", static_cast<long>(entry), 1.01);
  const Eigen::MatrixXd planted =
      named(sim.subsystem_blocks("cylinder", false), "dR/dp").sample.analytic;
  for (Eigen::Index e = 0; e < before.size(); ++e)
    EXPECT_EQ(planted(e), e == entry ? before(e) * 1.01 : before(e)) << e;
  sim.plant_derivative_error("cylinder", "dR/dp", static_cast<long>(entry), 1.0);
  EXPECT_EQ(named(sim.subsystem_blocks("cylinder", false), "dR/dp").sample.analytic, before);
  // The formulation's tangent blocks likewise.
  const Eigen::MatrixXd dx = sim.formulation_blocks(false).block[0].analytic;
  entry = largest_entry(dx);
  sim.plant_derivative_error("", "dr/dx", static_cast<long>(entry), 0.5);
  EXPECT_EQ(sim.formulation_blocks(false).block[0].analytic(entry), 0.5 * dx(entry));
  sim.plant_derivative_error("", "dr/dx", static_cast<long>(entry), 1.0);
  const auto refused = [&](const std::string& instance, const std::string& block) {
    try {
      sim.plant_derivative_error(instance, block, 0, 1.01);
    } catch (const std::invalid_argument& err) {
      return std::string(err.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refused("cylinder", "dR/dq")
                .find("'dR/dq' is not one of a subsystem's derivative "
                      "blocks (dR/dy, dR/dydot, dR/dp, dR/dv, dF/dy, "
                      "dF/dydot, dF/dp, dF/dv)"),
            std::string::npos);
  EXPECT_NE(refused("", "dR/dy").find("the formulation's tangent blocks (dr/dx, dr/dxd, dr/dxdd)"),
            std::string::npos);
  EXPECT_NE(refused("piston", "dR/dy").find("no subsystem instance 'piston' (the model's: V1, "),
            std::string::npos);
}

}  // namespace
}  // namespace mh
