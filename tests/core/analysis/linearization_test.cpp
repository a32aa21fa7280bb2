// The linearisation of a running model (core/src/analysis/linearization.cpp)
// against closed forms: a damped slider's pair of eigenvalues, a volume
// discharged through a throttle, the four-bar's spool against its own
// equation; the two formulations against each other on the four-bar; and
// the run it was taken from, which goes on to the bit as if it had not been.
#include "monohydra/core/linearization.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/run_state.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

constexpr double kMass = 2.0;        // kg
constexpr double kStiffness = 50.0;  // N/m
constexpr double kDamping = 3.0;     // N s/m

// A slider on the x axis held by a spring-damper between the ground at
// x = -1 and its origin (free length 1: the force is -k x - c xd), released
// from x = 0.1 at rest.
ModelFile slider() {
  return parse_model_text(R"(
units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - name: slider
    parent: ground
    joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]}
    mass: )" + std::to_string(kMass) +
                              R"(
    com: [0, 0, 0]
    inertia: [1, 1, 1]
    z0: 0.1
subsystems:
  - name: holder
    type: spring-damper
    points:
      a: {body: ground, at: [-1, 0, 0]}
      b: {body: slider, at: [0, 0, 0]}
    stiffness: )" + std::to_string(kStiffness) +
                              R"(
    damping: )" + std::to_string(kDamping) +
                              R"(
    free_length: 1.0
formulation: open-loop
integrator: trapezoidal
solver: {dt: 0.001, t_end: 1}
)",
                          "slider.yaml");
}

// A hose at 5 MPa discharged to a tank at 0.1 MPa through a throttle (a body
// with no force on it, as every model has one).
constexpr double kVolume = 1e-4, kFluidModulus = 1.5e9, kWallModulus = 1e9;  // m^3, Pa, Pa
constexpr double kArea = 1e-8, kDischarge = 0.7, kDensity = 850.0;           // m^2, -, kg/m^3
constexpr double kTank = 1e5;                                                // Pa
ModelFile discharge() {
  return parse_model_text(R"(
units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 1.0, com: [0, 0, 0], inertia: [1, 1, 1]}
subsystems:
  - {name: tank, type: pressure-source, ports: {p: tank}, pressure: 1e5}
  - {name: line, type: throttle, ports: {a: n, b: tank}, area: 1e-8, discharge_coefficient: 0.7, density: 850}
  - {name: hose, type: volume, ports: {p: n}, volume: 1e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 5e6}
nodes: {n: p, tank: null}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)",
                          "discharge.yaml");
}

ModelFile fourbar() {
  return load_model_file(test::source_path("models/fourbar.yaml"));
}

int index_of(const std::vector<LinearVariable>& vars, const std::string& name) {
  for (size_t i = 0; i < vars.size(); ++i)
    if (vars[i].name == name) return static_cast<int>(i);
  return -1;
}

void advance_to(Simulation& sim, double t) {
  while (sim.time() < t - 1e-9) sim.step();
}

TEST(Linearization, DampedSliderHasTheClosedFormPairOfEigenvalues) {
  const ModelFile file = slider();
  Simulation sim(file, test::build_plugins());
  sim.start();
  advance_to(sim, 0.1);
  const Linearization lin = linearize(sim, {"z1", "z1_dot"});
  ASSERT_EQ(lin.A.rows(), 2);
  const double w = std::sqrt(kStiffness / kMass),
               zeta = kDamping / (2.0 * std::sqrt(kStiffness * kMass));
  const std::complex<double> expected(-zeta * w, w * std::sqrt(1.0 - zeta * zeta));
  const std::vector<std::complex<double>> ev = eigenvalues(lin.A);
  ASSERT_EQ(ev.size(), 2u);
  const double error = std::abs(ev[0] - expected) / std::abs(expected);
  std::printf("  slider: eigenvalue %.9g %+.9gi, closed form %.9g %+.9gi, relative error %.2e\n",
              ev[0].real(), ev[0].imag(), expected.real(), expected.imag(), error);
  RecordProperty("eigenvalue_relative_error", test::scientific(error));
  EXPECT_LT(error, 1e-3);
  EXPECT_NEAR(ev[1].imag(), -expected.imag(), 1e-3 * std::abs(expected));
  // The outputs are the states themselves: C picks them, D is zero.
  const int x = index_of(lin.states, "z1"), v = index_of(lin.states, "z1_dot");
  ASSERT_GE(x, 0);
  ASSERT_GE(v, 0);
  EXPECT_EQ(lin.states[static_cast<size_t>(x)].unit, "m");
  EXPECT_EQ(lin.states[static_cast<size_t>(v)].unit, "m/s");
  EXPECT_NEAR(lin.C(0, x), 1.0, 1e-6);
  EXPECT_NEAR(lin.C(0, v), 0.0, 1e-6);
  EXPECT_NEAR(lin.C(1, v), 1.0, 1e-6);
  EXPECT_EQ(lin.B.cols(), 0);
  EXPECT_EQ(lin.D.cols(), 0);
  EXPECT_DOUBLE_EQ(lin.t, sim.time());
}

TEST(Linearization, VolumeThroughAThrottleHasTheOrificeSlopeOverTheCapacitance) {
  const ModelFile file = discharge();
  Simulation sim(file, test::build_plugins());
  sim.start();
  advance_to(sim, 0.05);
  const int p_state = sim.state_index("p");
  ASSERT_GE(p_state, 0);
  const double p = sim.states()[p_state];
  ASSERT_GT(p - kTank, 10 * 2e5);  // turbulent: Q = C_vt sqrt(dp)
  const Linearization lin = linearize(sim, {"p"});
  const int k = index_of(lin.states, "p");
  ASSERT_GE(k, 0);
  EXPECT_EQ(lin.states[static_cast<size_t>(k)].unit, "Pa");
  // C dp/dt = -C_vt sqrt(p - p_t): d(dp/dt)/dp = -C_vt / (2 C sqrt(p - p_t)).
  const double capacitance = kVolume * (1.0 / kFluidModulus + 1.0 / kWallModulus);
  const double c_vt = kDischarge * kArea * std::sqrt(2.0 / kDensity);
  const double expected = -c_vt / (2.0 * capacitance * std::sqrt(p - kTank));
  const double error = std::abs(lin.A(k, k) - expected) / std::abs(expected);
  std::printf("  discharge: A_pp %.9g 1/s, closed form %.9g 1/s, relative error %.2e\n",
              lin.A(k, k), expected, error);
  RecordProperty("eigenvalue_relative_error", test::scientific(error));
  EXPECT_LT(error, 1e-3);
  // The free slider is decoupled from the hose: its rows in p are zero.
  for (Eigen::Index i = 0; i < lin.A.rows(); ++i)
    if (i != k) {
      EXPECT_NEAR(lin.A(i, k), 0.0, 1e-9 * std::abs(expected));
    }
  EXPECT_NEAR(lin.C(0, k), 1.0, 1e-6);
}

// The spool's row, tau dU/dt = U_ref - U: B's entry of U in valve_command is
// 1/tau and A's -1/tau, whatever the rest of the circuit does.
TEST(Linearization, FourbarSpoolTakesTheValveCommandWithItsTimeConstant) {
  const ModelFile file = fourbar();
  for (const char* formulation : {"double-step", "penalty"}) {
    Simulation sim(file, test::build_plugins(), formulation);
    sim.start();
    advance_to(sim, 0.5);
    const Linearization lin = linearize(sim, {"U", "s"});
    ASSERT_EQ(lin.inputs.size(), 1u);
    EXPECT_EQ(lin.inputs[0].name, "valve_command");
    const int u = index_of(lin.states, "U");
    ASSERT_GE(u, 0) << formulation;
    const double tau = 4.547e-3;
    EXPECT_NEAR(lin.B(u, 0), 1.0 / tau, 1e-4 / tau) << formulation;
    EXPECT_NEAR(lin.A(u, u), -1.0 / tau, 1e-4 / tau) << formulation;
    // Only through U: every other entry of B is small beside what the
    // command moves through U within a step, h (A B)_i + h^2 (A^2 B)_i / 2.
    const Eigen::VectorXd ab = lin.A * lin.B.col(0), aab = lin.A * ab;
    // (The mechanical rows, three couplings from the command, show 1e-2 to
    // 1e-1 of that bound as the differences' error: not checked here.)
    for (Eigen::Index i = 0; i < lin.B.rows(); ++i)
      if (i != u && lin.states[static_cast<size_t>(i)].unit == "Pa") {
        const double through_u = lin.h * std::abs(ab[i]) + 0.5 * lin.h * lin.h * std::abs(aab[i]);
        EXPECT_LT(std::abs(lin.B(i, 0)), 1e-3 * through_u)
            << formulation << ", " << lin.states[static_cast<size_t>(i)].name;
      }
    // One step of the run itself from the command moved by +-du: the change
    // of U is Gamma = h (I - hA/2)^-1 B's entry.
    const double h = lin.h;
    const Eigen::MatrixXd gamma =
        (Eigen::MatrixXd::Identity(lin.A.rows(), lin.A.cols()) - 0.5 * h * lin.A)
            .partialPivLu()
            .solve(h * lin.B);
    const RunState saved = sim.save_state();
    const double u0 = sim.input(0), du = 1e-4;
    double moved[2];
    for (int side = 0; side < 2; ++side) {
      sim.restore_state(saved);
      sim.set_input(0, u0 + (side == 0 ? du : -du));
      sim.step();
      moved[side] = sim.states()[sim.state_index("U")];
    }
    const double stepped = (moved[0] - moved[1]) / (2.0 * du);
    std::printf("  %s: Gamma_U %.9g, one step's dU/du %.9g\n", formulation, gamma(u, 0), stepped);
    EXPECT_NEAR(gamma(u, 0), stepped, 1e-6 * std::abs(stepped)) << formulation;
    // s (the stroke) is the cylinder's output: not moved by the command at once.
    EXPECT_NEAR(lin.D(1, 0), 0.0, 1e-9) << formulation;
  }
}

// The eigenvalues of the formulations' A between 5 1/s and 1/(10 h) at a
// state where the mechanism moves (valve open). Below, the open-loop
// cylinder's near-integrator (its position hardly feeds back into the
// flows) sits within about 1 1/s of zero, where the differences' noise
// decides (+0.13 double-step, +1.09 penalty at t = 1.5 s).
std::vector<std::complex<double>> slow_eigenvalues(const std::string& formulation, double t) {
  const ModelFile file = fourbar();
  Simulation sim(file, test::build_plugins(), formulation);
  sim.start();
  advance_to(sim, t);
  const Linearization lin = linearize(sim, {});
  std::vector<std::complex<double>> slow;
  for (const std::complex<double>& v : eigenvalues(lin.A)) {
    if (std::abs(v) < 1.0 / (10.0 * lin.h) && std::abs(v) > 5.0) slow.push_back(v);
    std::printf("  %s at t = %g: %.6g %+.6gi\n", formulation.c_str(), t, v.real(), v.imag());
  }
  return slow;
}

// Measured at t = 1.5 s: the real pole (-34.73 against -34.78) agrees
// within 0.2 %, the boom's oscillation on the oil
// columns (-19.18 +- 57.89i against -19.68 +- 57.01i) within 1.7 %: the
// penalty formulation's projections enter its step map (Eqs. 20-21), the
// coordinate partitioning's do not.
TEST(Linearization, FourbarEigenvaluesAgreeBetweenDoubleStepAndPenaltyWithin2Percent) {
  const double t = 1.5;
  const std::vector<std::complex<double>> ds = slow_eigenvalues("double-step", t);
  const std::vector<std::complex<double>> pe = slow_eigenvalues("penalty", t);
  ASSERT_EQ(ds.size(), 3u);  // the pair and the real pole (the spool, -220, is beyond 1/(10 h))
  ASSERT_EQ(ds.size(), pe.size());
  for (size_t i = 0; i < ds.size(); ++i) {
    const double error = std::abs(ds[i] - pe[i]) / std::abs(ds[i]);
    std::printf("  double-step %.6g %+.6gi, penalty %.6g %+.6gi, relative %.2e\n", ds[i].real(),
                ds[i].imag(), pe[i].real(), pe[i].imag(), error);
    EXPECT_LT(error, ds[i].imag() != 0.0 ? 0.02 : 0.002) << "eigenvalue " << i;
  }
}

// What does agree: the penalty formulation's extra states (its coordinates
// and velocities across the constraints, 2 x 2 for the four-bar's cut
// joint) show as eigenvalues at -2/h, and the spool's and the stiff
// chamber's poles are the same in both within 0.1 %.
TEST(Linearization, FourbarPenaltyExtraStatesSitAtMinusTwoOverH) {
  const ModelFile file = fourbar();
  std::vector<std::complex<double>> ev[2];
  double h = 0.0;
  for (int f = 0; f < 2; ++f) {
    Simulation sim(file, test::build_plugins(), f == 0 ? "double-step" : "penalty");
    sim.start();
    advance_to(sim, 1.5);
    const Linearization lin = linearize(sim, {});
    h = lin.h;
    ev[f] = eigenvalues(lin.A);
  }
  ASSERT_EQ(ev[0].size() + 4, ev[1].size());
  int at_two_over_h = 0;
  for (const auto& v : ev[1]) at_two_over_h += std::abs(v + 2.0 / h) < 1e-3 * 2.0 / h ? 1 : 0;
  EXPECT_EQ(at_two_over_h, 4);
  for (const double pole : {-1.0 / 4.547e-3}) {
    const auto near = [&](const std::vector<std::complex<double>>& list) {
      return *std::min_element(list.begin(), list.end(), [&](auto a, auto b) {
        return std::abs(a - pole) < std::abs(b - pole);
      });
    };
    EXPECT_NEAR(near(ev[0]).real(), pole, 1e-3 * std::abs(pole));
    EXPECT_NEAR(near(ev[1]).real(), pole, 1e-3 * std::abs(pole));
  }
  // The fastest physical pole (the piston chamber's stiffness): both.
  EXPECT_NEAR(ev[0].back().real(), ev[1].back().real(), 1e-3 * std::abs(ev[0].back().real()));
}

// Every value of every step of a run, as one vector.
std::vector<double> record(const Simulation& sim) {
  std::vector<double> v(sim.z().data(), sim.z().data() + sim.z().size());
  v.insert(v.end(), sim.zd().data(), sim.zd().data() + sim.zd().size());
  v.insert(v.end(), sim.states().data(), sim.states().data() + sim.states().size());
  v.insert(v.end(), sim.outputs().data(), sim.outputs().data() + sim.outputs().size());
  v.push_back(sim.time());
  return v;
}

TEST(Linearization, RunGoesOnToTheBitAsIfItHadNotBeenLinearized) {
  const ModelFile file = fourbar();
  for (const char* formulation : {"double-step", "penalty"}) {
    Simulation plain(file, test::build_plugins(), formulation);
    Simulation probed(file, test::build_plugins(), formulation);
    plain.start();
    probed.start();
    std::vector<std::vector<double>> a, b;
    while (plain.time() < 1.2 - 1e-9) {
      plain.step();
      a.push_back(record(plain));
    }
    while (probed.time() < 1.2 - 1e-9) {
      // At 0.3 s and at 1.0 s, where the command's table jumps.
      if (probed.step_index() == 300 || probed.step_index() == 1000)
        (void)linearize(probed, {"U", "s", "z1_dot"});
      probed.step();
      b.push_back(record(probed));
    }
    ASSERT_EQ(a.size(), b.size());
    for (size_t k = 0; k < a.size(); ++k)
      ASSERT_EQ(a[k], b[k]) << formulation << ", step " << k + 1;
    EXPECT_EQ(plain.counters().residual_evaluations, probed.counters().residual_evaluations)
        << formulation;
  }
}

// What a filter asks for (LinearizeOptions{false, false}): no input
// columns, and one-sided differences whose error, of the order of the
// perturbation (a Newton tolerance), leaves the step's map and the
// outputs' rows those of the central differences to well within what a
// filter's Jacobian needs. Measured on the four-bar at t = 1.5 s (the
// valve open): every column of Phi and C within 4e-5 of its size with
// double-step; with penalty the coordinates' and rates' rows within 9e-4.
// Penalty's chamber pressures after a move of its coordinates within the
// constraints are below what its steps resolve, either way: a move of a
// Newton tolerance (1e-7 rad) changes them by some 1e-3 Pa, below the
// pressures' tightened Newton tolerance, and the central differences of
// the same entries change sign with the order the steps are taken in.
TEST(Linearization, AFiltersOneSidedMapWithoutInputsIsTheCentralOnesToItsDifferencesError) {
  const ModelFile file = fourbar();
  for (const char* formulation : {"double-step", "penalty"}) {
    Simulation sim(file, test::build_plugins(), formulation);
    sim.start();
    advance_to(sim, 1.5);
    const Linearization central = linearize(sim, {"s", "p1", "z1_dot"});
    const Linearization filter = linearize(sim, {"s", "p1", "z1_dot"}, {false, false});
    EXPECT_TRUE(filter.inputs.empty()) << formulation;
    EXPECT_EQ(filter.Gamma.cols(), 0) << formulation;
    EXPECT_EQ(filter.B.cols(), 0) << formulation;
    ASSERT_EQ(filter.Phi.rows(), central.Phi.rows());
    const bool penalty = std::string(formulation) == "penalty";
    double worst = 0.0;
    for (Eigen::Index j = 0; j < central.Phi.cols(); ++j) {
      const bool moves_coordinates = penalty && j < 6;  // z1..z3, z1_dot..z3_dot
      const Eigen::Index rows = moves_coordinates ? 6 : central.Phi.rows();
      const double phi = (filter.Phi.col(j).head(rows) - central.Phi.col(j).head(rows)).norm() /
                         std::max(central.Phi.col(j).head(rows).norm(), 1e-300);
      const double c = moves_coordinates ? 0.0
                                         : (filter.C.col(j) - central.C.col(j)).norm() /
                                               std::max(central.Phi.col(j).norm(), 1e-300);
      worst = std::max({worst, phi, c});
    }
    std::printf("  %s: worst column of Phi or C off by %.3g of its size\n", formulation, worst);
    EXPECT_LT(worst, penalty ? 3e-3 : 1e-4) << formulation;
  }
}

TEST(Linearization, RefusesARunNotStartedAndAnUnknownOutputByName) {
  const ModelFile file = slider();
  Simulation sim(file, test::build_plugins());
  EXPECT_THROW((void)linearize(sim, {}), SimulationError);
  sim.start();
  try {
    (void)linearize(sim, {"z1", "no_such_value"});
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'no_such_value'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("z1_dot"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mh
