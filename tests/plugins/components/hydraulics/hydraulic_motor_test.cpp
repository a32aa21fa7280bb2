// The hydraulic motor (plugins/components/hydraulics/hydraulic_motor.cpp): through a fake
// host, its torque D (p_A - p_B) - friction as a pure couple about the axis on
// the rotor and the opposite on the housing, its speed read from the arms'
// velocities, its flow D omega + C_L dp, dissipation >= 0, the state jacobian
// and the point-force jacobian against central differences; in the core, a
// motor held at constant pressures spinning up one body against viscous
// friction, against the closed form omega(t) = omega_inf (1 - exp(-t/tau)).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "monohydra/core/run.hpp"
#include "monohydra/core/simulation.hpp"
#include "plugins/fake_host.hpp"
#include "test_support.hpp"

namespace mh::test {
namespace {

constexpr double kD = 50e-6 / (2.0 * 3.14159265358979323846);  // 50 cm^3/rev, m^3/rad
constexpr double kLeak = 2e-13, kViscous = 0.5, kCoulomb = 20.0, kOmegaS = 0.05;

using V3 = std::array<double, 3>;
V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// A motor whose axis runs along n = (1, 2, 2)/3 through (0.1, 0.2, 0.3): a slanted
// axis, so nothing leans on a coordinate axis.
struct Motor {
  FakeNetwork net;
  FakeHost host{net, "motor"};
  std::unique_ptr<Instance> instance;
  mh_status status = MH_ERROR;
  V3 n{1.0 / 3, 2.0 / 3, 2.0 / 3}, o{0.1, 0.2, 0.3};
  V3 u{2.0 / 3, 1.0 / 3, -2.0 / 3}, u2{};  // u, u2: normal to n and to each other

  Motor() {
    u2 = cross(n, u);
    host.numbers = {{"displacement", kD},
                    {"leakage_coefficient", kLeak},
                    {"viscous_friction", kViscous},
                    {"coulomb_friction", kCoulomb},
                    {"friction_speed", kOmegaS}};
    host.point_positions = {{"housing", at(0.0, 0.0, 0.0)},
                            {"rotor", at(0.4, 0.0, 0.0)},
                            {"housing_arm", at(0.0, 0.25, 0.0)},
                            {"rotor_arm", at(0.4, 0.3 * std::cos(0.7), 0.3 * std::sin(0.7))}};
    host.port_nodes = {{"A", "nA"}, {"B", "nB"}};
    instance = std::make_unique<Instance>("hydraulic-motor", host);
    status = instance->setup();
  }
  V3 at(double along, double cu, double cu2) const {
    V3 x;
    for (int i = 0; i < 3; ++i) x[i] = o[i] + along * n[i] + cu * u[i] + cu2 * u2[i];
    return x;
  }
  // Housing turning at wh, rotor at wr (rad/s, about n), both about the axis.
  Evaluation eval(double wh, double wr, double pa, double pb) const {
    Evaluation e(net, 4);
    const char* keys[4] = {"housing", "rotor", "housing_arm", "rotor_arm"};
    for (int k = 0; k < 4; ++k) {
      const V3 x = host.point_positions.at(keys[k]);
      const double w = (k == 0 || k == 2) ? wh : wr;
      V3 r;
      for (int i = 0; i < 3; ++i) r[i] = x[i] - o[i];
      const V3 v = cross({w * n[0], w * n[1], w * n[2]}, r);
      for (int i = 0; i < 3; ++i) {
        e.point_p[3 * k + i] = x[i];
        e.point_v[3 * k + i] = v[i];
      }
    }
    e.y[static_cast<size_t>(host.port("A").index)] = pa;
    e.y[static_cast<size_t>(host.port("B").index)] = pb;
    return e;
  }
  double out(const Evaluation& e, const char* name) const {
    return e.outputs[static_cast<size_t>(host.outputs.at(name))];
  }
};

double friction(double omega) {
  return kViscous * omega + kCoulomb * std::tanh(omega / kOmegaS);
}

TEST(HydraulicMotor, TorqueIsDTimesDpMinusFrictionAsAPureCoupleAboutTheAxis) {
  Motor m;
  ASSERT_EQ(m.status, MH_OK) << m.host.all_logs();
  for (double wr : {-3.0, -0.02, 0.0, 0.01, 5.0}) {
    const double wh = 0.4, pa = 12e6, pb = 1.5e6;
    Evaluation e = m.eval(wh, wr, pa, pb);
    ASSERT_EQ(e.run(*m.instance), MH_OK);
    const double omega = wr - wh, torque = kD * (pa - pb) - friction(omega);
    EXPECT_NEAR(m.out(e, "omega"), omega, 1e-12);
    EXPECT_NEAR(m.out(e, "torque"), torque, 1e-10 * std::abs(kD * (pa - pb)));
    // Per body (housing: points 0, 2; rotor: 1, 3): no net force, moment +-T n.
    for (int body = 0; body < 2; ++body) {
      V3 force{0, 0, 0}, moment{0, 0, 0};
      for (int k : {body, body + 2}) {
        V3 f, r;
        for (int i = 0; i < 3; ++i) {
          f[i] = e.point_f[3 * k + i];
          r[i] = e.point_p[3 * k + i];
          force[i] += f[i];
        }
        const V3 mk = cross(r, f);
        for (int i = 0; i < 3; ++i) moment[i] += mk[i];
      }
      const double sign = body == 1 ? 1.0 : -1.0;
      for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(force[i], 0.0, 1e-9 * std::abs(torque) + 1e-12);
        EXPECT_NEAR(moment[i], sign * torque * m.n[i], 1e-9 * std::abs(torque) + 1e-12) << wr;
      }
    }
  }
}

TEST(HydraulicMotor, FlowIsDTimesOmegaPlusLeakageFromAToB) {
  Motor m;
  ASSERT_EQ(m.status, MH_OK);
  const int32_t a = m.host.port("A").index, b = m.host.port("B").index;
  for (double wr : {-2.0, 0.0, 7.5}) {
    Evaluation e = m.eval(-0.3, wr, 9e6, 2e6);
    ASSERT_EQ(e.run(*m.instance), MH_OK);
    const double q = kD * (wr + 0.3) + kLeak * 7e6;
    EXPECT_NEAR(e.residual[static_cast<size_t>(a)], q, 1e-12 * std::abs(q) + 1e-18);
    EXPECT_EQ(e.residual[static_cast<size_t>(b)], -e.residual[static_cast<size_t>(a)]);
    EXPECT_EQ(m.out(e, "q"), e.residual[static_cast<size_t>(a)]);
  }
}

TEST(HydraulicMotor, DissipatesFrictionAndLeakageNeverNegative) {
  Motor m;
  ASSERT_EQ(m.status, MH_OK);
  for (double wr : {-4.0, -0.01, 0.0, 0.03, 6.0}) {
    for (double dp : {-5e6, 0.0, 8e6}) {
      Evaluation e = m.eval(0.0, wr, 2e6 + dp, 2e6);
      const mh_subsystem_eval rec = e.record();
      double stored = -1, dissipation = -1;
      ASSERT_EQ(m.instance->api()->energy(m.instance->api(), &rec, &stored, &dissipation), MH_OK);
      EXPECT_EQ(stored, 0.0);
      EXPECT_GE(dissipation, 0.0);
      // Power balance: hydraulic in = mechanical out + dissipation.
      EXPECT_NEAR(dp * (kD * wr + kLeak * dp), (kD * dp - friction(wr)) * wr + dissipation,
                  1e-9 * (std::abs(dp * kD * wr) + 1.0));
    }
  }
}

TEST(HydraulicMotor, StateJacobianMatchesCentralDifferences) {
  Motor m;
  ASSERT_EQ(m.status, MH_OK);
  const double err = jacobian_error(*m.instance, m.eval(0.2, 3.0, 10e6, 1e6));
  EXPECT_LT(err, 1e-6);
}

TEST(HydraulicMotor, PointForceJacobianMatchesCentralDifferences) {
  Motor m;
  ASSERT_EQ(m.status, MH_OK);
  const mh_subsystem* api = m.instance->api();
  ASSERT_NE(api->point_force_jacobian, nullptr);
  double worst = 0.0;
  for (double wr : {0.02, 2.0}) {
    Evaluation e = m.eval(0.5, wr, 10e6, 1e6);
    // Perturb off the rigid configuration too: the derivatives hold at any point state.
    e.point_p[10] += 0.01;
    e.point_v[4] -= 0.3;
    constexpr int n = 12;
    std::vector<double> dp(n * n, 0.0), dv(n * n, 0.0);
    {
      const mh_subsystem_eval rec = e.record();
      ASSERT_EQ(api->point_force_jacobian(api, &rec, dp.data(), dv.data()), MH_OK);
    }
    for (int which = 0; which < 2; ++which) {
      std::vector<double>& x = which == 0 ? e.point_p : e.point_v;
      const std::vector<double>& analytic = which == 0 ? dp : dv;
      double scale = 0.0;
      for (double d : analytic) scale = std::max(scale, std::abs(d));
      for (int col = 0; col < n; ++col) {
        const double x0 = x[col], h = 1e-6;
        x[col] = x0 + h;
        ASSERT_EQ(e.run(*m.instance), MH_OK);
        const std::vector<double> plus = e.point_f;
        x[col] = x0 - h;
        ASSERT_EQ(e.run(*m.instance), MH_OK);
        x[col] = x0;
        for (int row = 0; row < n; ++row) {
          const double fd = (plus[row] - e.point_f[row]) / (2 * h);
          worst = std::max(worst, std::abs(fd - analytic[row + n * col]) / scale);
        }
      }
    }
  }
  EXPECT_LT(worst, 1e-6);
  std::printf("[ measured ] hydraulic-motor point-force jacobian max error %.3g (of its largest)\n",
              worst);
}

TEST(HydraulicMotor, ArmOffThePlaneNormalToTheAxisIsRefusedNamingThePoint) {
  FakeNetwork net;
  FakeHost host(net, "motor");
  host.numbers = {{"displacement", kD}};
  host.point_positions = {{"housing", {0, 0, 0}},
                          {"rotor", {0, 0, 1}},
                          {"housing_arm", {1, 0, 0}},
                          {"rotor_arm", {1, 0, 1.2}}};
  Instance motor("hydraulic-motor", host);
  EXPECT_EQ(motor.setup(), MH_ERROR);
  EXPECT_NE(host.all_logs().find("'rotor_arm' must lie off the axis, in the plane normal"),
            std::string::npos)
      << host.all_logs();
  for (const auto& [key, value] :
       std::vector<std::pair<std::string, double>>{{"displacement", 0.0},
                                                   {"leakage_coefficient", -1e-12},
                                                   {"viscous_friction", -1.0},
                                                   {"coulomb_friction", -1.0},
                                                   {"friction_speed", 0.0}}) {
    Motor m;
    m.host.numbers[key] = value;
    m.host.option_errors.clear();
    Instance again("hydraulic-motor", m.host);
    EXPECT_EQ(again.setup(), MH_ERROR) << key;
    EXPECT_EQ(m.host.option_errors, std::vector<std::string>{key});
  }
}

// One body turning about the vertical z axis (J = 2 kg m^2 about it), driven by
// a motor between the pump (A, 10 MPa) and the tank (B, 0.1 MPa), viscous
// friction only: J omega' = D dp - c_v omega, so omega = omega_inf (1 - exp(-t c_v / J)),
// omega_inf = D dp / c_v, and the pump delivers D omega + C_L dp.
TEST(HydraulicMotor, SpinsUpOneBodyAsTheClosedFormAndThePumpDeliversDOmegaPlusLeakage) {
  const std::string model = R"(
units: {length: m, mass: kg, time: s, angle: rad}
name: motor-spin-up
gravity: [0, 0, -9.81]
bodies:
  - name: turret
    parent: ground
    joint: {type: revolute, at: [0, 0, 0], axis: [0, 0, 1]}
    mass: 50
    com: [0, 0, 0.5]
    inertia: [3, 3, 2]
    z0: 0
subsystems:
  - {name: pump, type: pressure-source, ports: {p: supply}, pressure: 10e6, states: {q: q_pump}}
  - {name: tank, type: pressure-source, ports: {p: return}, pressure: 1e5, states: {q: null}}
  - name: slew
    type: hydraulic-motor
    points:
      housing: {body: ground, at: [0, 0, 0]}
      rotor: {body: turret, at: [0, 0, 0.3]}
      housing_arm: {body: ground, at: [0.2, 0, 0]}
      rotor_arm: {body: turret, at: [0, 0.2, 0.3]}
    ports: {A: supply, B: return}
    displacement: 7.957747154594767e-6
    leakage_coefficient: 1e-12
    viscous_friction: 0.8
    outputs: {omega: omega, torque: torque, q: q_motor}
nodes: {supply: null, return: null}
formulation: open-loop
solver: {dt: 0.001, t_end: 5}
)";
  const ModelFile file = parse_model_text(model, "motor.yaml");
  Simulation sim(file, build_plugins());
  sim.start();
  const double d = 7.957747154594767e-6, dp = 10e6 - 1e5, c = 0.8, j = 2.0, leak = 1e-12;
  const double omega_inf = d * dp / c, tau = j / c;
  const int omega_out = sim.output_index("omega"), torque_out = sim.output_index("torque");
  const int q_pump = sim.state_index("q_pump");
  ASSERT_GE(omega_out, 0);
  ASSERT_GE(q_pump, 0);
  double worst_omega = 0.0, worst_angle = 0.0, worst_torque = 0.0, worst_flow = 0.0;
  while (sim.time() < 5.0 - 1e-9) {
    sim.step();
    const double t = sim.time(), e = std::exp(-t / tau);
    const double omega = omega_inf * (1 - e), angle = omega_inf * (t - tau * (1 - e));
    worst_omega = std::max(worst_omega, std::abs(sim.outputs()[omega_out] - omega));
    worst_angle = std::max(worst_angle, std::abs(sim.z()[0] - angle));
    worst_torque =
        std::max(worst_torque, std::abs(sim.outputs()[torque_out] - (d * dp - c * omega)));
    worst_flow = std::max(worst_flow, std::abs(sim.states()[q_pump] - (d * omega + leak * dp)));
  }
  EXPECT_LT(worst_omega, 1e-5 * omega_inf);
  EXPECT_LT(worst_angle, 1e-5 * omega_inf * 5.0);
  EXPECT_LT(worst_torque, 1e-5 * d * dp);
  EXPECT_LT(worst_flow, 1e-5 * d * omega_inf);
  EXPECT_NEAR(sim.z()[0], omega_inf * (5.0 - tau * (1 - std::exp(-5.0 / tau))), 1e-4);
  std::printf(
      "[ measured ] motor spin-up vs closed form: omega %.3g rad/s (of %.4g), angle %.3g "
      "rad, torque %.3g N m, pump flow %.3g m^3/s\n",
      worst_omega, omega_inf, worst_angle, worst_torque, worst_flow);
}

// A motor on a moving housing, in 3D: an upper carriage slews freely about
// the vertical; on it, a boom turns about a horizontal axis, driven by a motor
// whose housing is the carriage. The host's K = d(M' zdd - Q')/dz and C =
// d/dzd (mech_derivatives, which take the motor's exact point-force jacobian)
// against central differences of the dynamics, mid-motion.
TEST(HydraulicMotor, OnASlewingCarriageTheHostsKAndCMatchDifferencesOfTheDynamics) {
  const std::string model = R"(
units: {length: m, mass: kg, time: s, angle: rad}
name: motor-on-carriage
gravity: [0, 0, -9.81]
bodies:
  - name: upper
    parent: ground
    joint: {type: revolute, at: [0, 0, 0], axis: [0, 0, 1]}
    mass: 200
    com: [0.2, 0, 0.5]
    inertia: [20, 20, 30]
    z0: 0.3
  - name: boom
    parent: upper
    joint: {type: revolute, at: [0.5, 0, 1], axis: [0, 1, 0]}
    mass: 40
    com: [1, 0, 0]
    inertia: [1, 10, 10]
    z0: -0.4
subsystems:
  - {name: VA, type: volume, ports: {p: nA}, volume: 1e-3, bulk_modulus: 550e6,
     fluid_bulk_modulus: 1500e6, initial_pressure: 8e6}
  - {name: VB, type: volume, ports: {p: nB}, volume: 1e-3, bulk_modulus: 550e6,
     fluid_bulk_modulus: 1500e6, initial_pressure: 1e6}
  - name: drive
    type: hydraulic-motor
    points:
      housing: {body: upper, at: [0.5, 0, 1]}
      rotor: {body: boom, at: [0, 0.3, 0]}
      housing_arm: {body: upper, at: [0.8, 0, 1]}
      rotor_arm: {body: boom, at: [0.3, 0.3, 0]}
    ports: {A: nA, B: nB}
    displacement: 5e-5
    leakage_coefficient: 1e-12
    viscous_friction: 2
    coulomb_friction: 30
    friction_speed: 0.5
nodes: {nA: pA, nB: pB}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";
  const ModelFile file = parse_model_text(model, "carriage.yaml");
  Simulation sim(file, build_plugins());
  sim.start();
  for (int k = 0; k < 150; ++k) sim.step();
  const Eigen::VectorXd z = sim.z(), zd = sim.zd(), zdd = sim.zdd();
  ASSERT_GT(std::abs(zd[1]), 0.05);  // the boom is turning
  // The couple's work on the bodies balances their energy (KE + PE - W = drift) to the
  // trapezoidal rule's error: 4.3e-5 of W at dt = 1 ms, a quarter of that at dt / 2.
  EXPECT_LT(std::abs(sim.drift()), 1e-4 * std::abs(sim.work()));
  std::printf("[ measured ] work %.6g J, drift %.3g J\n", sim.work(), sim.drift());
  const auto d = sim.mechanics_derivatives(z, zd, zdd);
  Eigen::MatrixXd K(2, 2), C(2, 2);
  for (int k = 0; k < 2; ++k) {
    const double h = 1e-6;
    Eigen::VectorXd zp = z, zm = z, vp = zd, vm = zd;
    zp[k] += h;
    zm[k] -= h;
    vp[k] += h;
    vm[k] -= h;
    K.col(k) = (sim.dynamics_residual(zp, zd, zdd) - sim.dynamics_residual(zm, zd, zdd)) / (2 * h);
    C.col(k) = (sim.dynamics_residual(z, vp, zdd) - sim.dynamics_residual(z, vm, zdd)) / (2 * h);
  }
  const double k_err = (d.K - K).lpNorm<Eigen::Infinity>() / K.lpNorm<Eigen::Infinity>();
  const double c_err = (d.C - C).lpNorm<Eigen::Infinity>() / C.lpNorm<Eigen::Infinity>();
  EXPECT_LT(k_err, 1e-6);
  EXPECT_LT(c_err, 1e-6);
  EXPECT_GT(std::abs(C(1, 1)), 2.0);  // the motor's friction shows in C
  std::printf("[ measured ] motor on a slewing carriage: K error %.3g, C error %.3g (relative)\n",
              k_err, c_err);
}

}  // namespace
}  // namespace mh::test
