// The extended Kalman filter (core/src/estimation/extended_kalman_filter.cpp)
// by the three-simulation test on the four-bar (three_simulations.hpp), in
// four sensor configurations.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

#include "core/sensitivities/parameter_directions.hpp"
#include "monohydra/core/filter_defaults.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/sensitivities.hpp"
#include "monohydra/cpp/number_text.hpp"
#include "three_simulations.hpp"

namespace mh {
namespace {

using test::build_plugins;
using test::expect_tracks;
using test::fourbar;
using test::kPressureNoise;
using test::Outcome;
using test::source_path;
using test::three_simulations;
using test::tuned_noise;

TEST(ExtendedKalmanFilter,
     EncoderAndBothChamberPressuresTrackTheMachineTenTimesCloserThanTheModel) {
  const Outcome o = three_simulations({{"encoder", "z1", 1e-4, 0.0},
                                       {"pA", "p2", kPressureNoise, 0.0},
                                       {"pB", "p3", kPressureNoise, 0.0}},
                                      {1, 1, 1}, 4.0, 1);
  expect_tracks(o);
  EXPECT_GT(o.nees_inside, 0.8);
}

// The crank's encoder alone sees the mechanism, and the chambers'
// pressures only through their difference, which moves it: their common
// level stays about a third of the open loop's error.
TEST(ExtendedKalmanFilter, AnEncoderAloneTracksTheMechanismButLessThePressures) {
  const Outcome o = three_simulations({{"encoder", "z1", 1e-4, 0.0}}, {1}, 4.0, 4);
  EXPECT_LT(o.filter_rms[0], 0.1 * o.open_rms[0]);
  for (Eigen::Index i = 2; i < 5; ++i)
    EXPECT_LT(o.filter_rms[i], 0.5 * o.open_rms[i]) << o.names[static_cast<size_t>(i)];
  EXPECT_LT(o.nees_above, 0.1);
}

TEST(ExtendedKalmanFilter, AStrokeSensorAloneTracksTheMachineTenTimesCloserThanTheModel) {
  expect_tracks(three_simulations({{"stroke", "s", 1e-5, 0.0}}, {1}, 4.0, 2));
}

TEST(ExtendedKalmanFilter, AnEncoderAt100HzWithPressuresAt1kHzTracksTheMachine) {
  expect_tracks(three_simulations({{"encoder", "z1", 1e-4, 0.0},
                                   {"pA", "p2", kPressureNoise, 0.0},
                                   {"pB", "p3", kPressureNoise, 0.0}},
                                  {10, 1, 1}, 4.0, 3));
}

// Joint estimation (Khadim et al. 2021's augmented filter): the machine's
// valve passes 20 % more than the model's, or its load is 15 % heavier; the
// filter starts from the model's value, 20 % uncertain, and estimates it
// beside the state from the encoder and both chamber pressures.
struct Joint {
  double estimate = 0.0, sd = 0.0, truth = 0.0;
};

Joint estimate_parameter(const ParameterDirection& p, double truth_value) {
  const double t_end = 4.0;
  const ModelFile nominal = fourbar(t_end);
  ModelFile machine = nominal;
  for (SubsystemSpec& s : machine.subsystems)
    if (s.name == p.subsystem) s.options.at(p.key).number = truth_value;
  for (const ParameterDirection::BodyChange& b : p.bodies) {
    Body& body = machine.model.bodies[static_cast<size_t>(b.body)];
    body.mass += (truth_value - p.value) * b.mass;
    body.inertia_B += (truth_value - p.value) * b.inertia;
  }
  Simulation truth(machine, build_plugins());
  Simulation estimated(nominal, build_plugins());
  truth.start();
  estimated.start();
  FilterNoise noise = tuned_noise(state_variables(estimated));
  noise.parameter_plant = Eigen::VectorXd::Zero(1);
  noise.parameter_initial = Eigen::VectorXd::Constant(1, 0.2 * std::abs(p.value));
  ExtendedKalmanFilter filter(estimated, test::encoder_and_pressures(), noise, {p});
  test::filter_along(truth, filter, std::lround(t_end / nominal.solver.dt), 5);
  const Eigen::Index j = filter.covariance().rows() - 1;
  const Joint out{filter.state()[j], std::sqrt(filter.covariance()(j, j)), truth_value};
  if (std::getenv("MH_EKF_PRINT") != nullptr)
    std::printf("%s: %.6g +- %.3g, truth %.6g (%.3f %% off)\n", p.path.c_str(), out.estimate,
                out.sd, out.truth, 100.0 * (out.estimate - out.truth) / out.truth);
  return out;
}

TEST(ExtendedKalmanFilter, EstimatesTheValvesFlowCoefficientBesideTheStateToAPercent) {
  const ModelFile file = fourbar(4.0);
  const ParameterDirection p = test::option_direction(file, "valve", "flow_coefficient");
  const Joint j = estimate_parameter(p, 1.2 * p.value);
  EXPECT_LT(std::abs(j.estimate - j.truth), 0.01 * j.truth) << j.estimate << " +- " << j.sd;
  EXPECT_LT(std::abs(j.estimate - j.truth), 3.0 * j.sd) << j.estimate << " +- " << j.sd;
}

// The load's mass acts on the sensors only while the mechanism moves (1 s
// to 2.5 s of the 4): the data determine it to about an eighth (6 kg of 50
// measured, from 10), and the filter says so: its interval holds the truth
// and has narrowed by a quarter at least.
TEST(ExtendedKalmanFilter, TheLoadsMassBesideTheStateIsLearnedWithAnHonestInterval) {
  const ModelFile file = fourbar(4.0);
  const ParameterDirection p = test::mass_direction(file.model, 2);
  const Joint j = estimate_parameter(p, 1.15 * p.value);
  EXPECT_LT(std::abs(j.estimate - j.truth), 3.0 * j.sd) << j.estimate << " +- " << j.sd;
  EXPECT_LT(j.sd, 0.75 * 0.2 * p.value) << j.estimate << " +- " << j.sd;
}

// A table valve's characteristic curve, point by point (Khadim et al. 2021
// identified one on this four-bar with an augmented filter): the model's
// valve is a valve-table whose five openings (2 to 10 V, at 1 MPa) pass an
// orifice's straight line of flows; the machine's passes 20 % less to 15 %
// more, opening by opening. The command steps the spool to each opening and
// back (out and home, 0.4 s each), and the filter, from the encoder and both
// chamber pressures, estimates the five flows beside the state, each from
// the model's value 20 % uncertain.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  if (at == std::string::npos) throw std::logic_error("models/fourbar.yaml has no '" + from + "'");
  return text.replace(at, from.size(), to);
}

constexpr std::array<double, 5> kOpenings = {2.0, 4.0, 6.0, 8.0, 10.0};  // V

ModelFile table_fourbar(const std::array<double, 5>& flows, double t_end) {
  std::ifstream in(source_path("models/fourbar.yaml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string table = "[", command = "[[0, 0], [0.3, 0]";
  double t = 0.3;
  for (size_t i = 0; i < kOpenings.size(); ++i) {
    table += (i > 0 ? ", [" : "[") + std::to_string(kOpenings[i]) + ", 1e6, " +
             monohydra::exact_number(flows[i]) + "]";
    for (const double u : {kOpenings[i], -kOpenings[i]}) {
      command += ", [" + std::to_string(t) + ", " + std::to_string(u) + "], [" +
                 std::to_string(t + 0.4) + ", " + std::to_string(u) + "]";
      t += 0.4;
    }
  }
  command += ", [" + std::to_string(t) + ", 0]]";
  std::string yaml = replaced(text.str(), "type: valve-4-3", "type: valve-table");
  yaml = replaced(yaml, "flow_coefficient: 2.138e-8", "flow_table: " + table + "]");
  yaml = replaced(yaml,
                  "table: [[0, 0], [1, 0], [1, 10], [2.5, 10], [2.5, 0], [5, 0], [5, -10], "
                  "[8, -10], [8, 0]]",
                  "table: " + command);
  ModelFile file = parse_model_text(yaml, "fourbar.yaml with a table valve", source_path("models"));
  file.solver.t_end = t_end;
  return file;
}

TEST(ExtendedKalmanFilter, LearnsATableValvesCharacteristicCurvePointByPointToAPercent) {
  const double t_end = 4.5;
  const std::array<double, 5> machine_factor = {0.80, 0.90, 1.05, 1.15, 1.10};
  std::array<double, 5> nominal_flows{}, machine_flows{};
  std::vector<ParameterDirection> params;
  for (size_t i = 0; i < kOpenings.size(); ++i) {
    nominal_flows[i] = 2.138e-8 * kOpenings[i] * 1e3;  // C_vd u sqrt(1 MPa)
    machine_flows[i] = machine_factor[i] * nominal_flows[i];
    ParameterDirection p;
    p.subsystem = "valve";
    p.key = "flow_table/" + std::to_string(i) + "/2";
    p.path = "subsystems/valve/" + p.key;
    p.value = nominal_flows[i];
    p.option = 1.0;
    params.push_back(p);
  }
  const ModelFile machine_file = table_fourbar(machine_flows, t_end);
  const ModelFile nominal_file = table_fourbar(nominal_flows, t_end);
  Simulation truth(machine_file, build_plugins());
  Simulation estimated(nominal_file, build_plugins());
  truth.start();
  estimated.start();
  const auto k = static_cast<Eigen::Index>(params.size());
  FilterNoise noise = tuned_noise(state_variables(estimated));
  noise.parameter_plant = Eigen::VectorXd::Zero(k);
  noise.parameter_initial.resize(k);
  for (Eigen::Index i = 0; i < k; ++i)
    noise.parameter_initial[i] = 0.2 * params[static_cast<size_t>(i)].value;
  ExtendedKalmanFilter filter(estimated, test::encoder_and_pressures(), noise, params);
  test::filter_along(truth, filter, std::lround(t_end / estimated.settings().dt), 6);
  // The curve's RMS error relative to the machine's flows, and each point
  // inside three of its standard deviations.
  const Eigen::Index first = filter.state().size() - k;
  double squares = 0.0;
  for (Eigen::Index i = 0; i < k; ++i) {
    const double estimate = filter.state()[first + i];
    const double sd = std::sqrt(filter.covariance()(first + i, first + i));
    const double machine = machine_flows[static_cast<size_t>(i)];
    squares += std::pow((estimate - machine) / machine, 2);
    EXPECT_LT(std::abs(estimate - machine), 3.0 * sd)
        << params[static_cast<size_t>(i)].path << ": " << estimate << " +- " << sd << ", machine "
        << machine;
    if (std::getenv("MH_EKF_PRINT") != nullptr)
      std::printf("%s: %.6g +- %.3g, machine %.6g (%.3f %% off), model %.6g\n",
                  params[static_cast<size_t>(i)].path.c_str(), estimate, sd, machine,
                  100.0 * (estimate - machine) / machine, params[static_cast<size_t>(i)].value);
  }
  EXPECT_LT(std::sqrt(squares / static_cast<double>(k)), 0.01);
}

// The excavator's payload weighed on line (Pyrhonen et al., Nonlinear Dyn.
// 2023, weigh a crane's so): the machine's bucket takes 1800 kg of soil
// at 1 s, a box 1.0 x 1.1 x 0.6 m whose centre is 0.1 m forward of the
// bucket's and 0.05 m above it (the pair's mass, centre of mass and inertia
// computed here by parallel axes); the model's bucket is empty. The filter
// estimates the load beside the state as bodies/bucket/payload/mass does:
// a mass at that centre, moving the bucket's first moment and inertia about
// its origin linearly (about_origin), from the excavator's sensors (the
// three joint encoders and the three cylinders' head-side pressures) every
// step, with a random walk of 30 kg per sqrt(s) that lets it follow a change.
TEST(ExtendedKalmanFilter, AnExcavatorsPayloadIsWeighedToTwoPercentWithinFiveSecondsOfItsPickUp) {
  const double t_pick = 1.0, t_end = t_pick + 5.0, payload = 1800.0;
  ModelFile file = load_model_file(source_path("models/excavator.yaml"));
  file.solver.t_end = t_end;
  size_t bucket = 0;
  while (file.model.bodies[bucket].name != "bucket") ++bucket;
  const Body empty = file.model.bodies[bucket];
  const auto point = [](double m, const Eigen::Vector3d& d) {
    return Eigen::Matrix3d(m * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()));
  };
  const Eigen::Vector3d centre = empty.com_B + Eigen::Vector3d(0.1, 0.0, 0.05);
  const Eigen::Vector3d d2 = Eigen::Vector3d(1.0, 1.1, 0.6).cwiseAbs2();
  const Eigen::Matrix3d own_per_kg =
      (Eigen::Vector3d(d2.y() + d2.z(), d2.x() + d2.z(), d2.x() + d2.y()) / 12.0).asDiagonal();
  const double loaded = empty.mass + payload;
  const Eigen::Vector3d com = (empty.mass * empty.com_B + payload * centre) / loaded;
  const Eigen::Matrix3d inertia = empty.inertia_B + point(empty.mass, empty.com_B - com) +
                                  payload * own_per_kg + point(payload, centre - com);

  Simulation truth(file, build_plugins());
  Simulation estimated(file, build_plugins());
  truth.start();
  estimated.start();
  ParameterDirection p;
  p.path = "bodies/bucket/payload/mass";
  p.bodies.push_back(
      {static_cast<int>(bucket), 1.0, centre, point(1.0, centre) + own_per_kg, true});
  FilterNoise noise = default_filter_noise(state_variables(estimated), {p});
  noise.parameter_plant = Eigen::VectorXd::Constant(1, 30.0);
  noise.parameter_initial = Eigen::VectorXd::Constant(1, 500.0);
  std::vector<FilterSensor> sensors;
  for (const SensorSpec& s : file.sensors) sensors.push_back(filter_sensor(s, "excavator.yaml"));
  ExtendedKalmanFilter filter(estimated, sensors, noise, {p});
  const double dt = estimated.settings().dt;
  const long steps = std::lround(t_end / dt), pick = std::lround(t_pick / dt);
  const Eigen::Index j = filter.state().size() - 1;
  double before = 0.0;
  test::filter_along(
      truth, filter, steps, 7,
      [&](long step) {
        if (step != pick) return;
        before = filter.state()[j];
        truth.set_body_inertia(static_cast<int>(bucket), loaded, com, inertia);
      },
      [&](long step) {
        if (std::getenv("MH_EKF_PRINT") != nullptr && step % 500 == 0)
          std::printf("t %.1f s: payload %.1f +- %.1f kg\n", static_cast<double>(step) * dt,
                      filter.state()[j], std::sqrt(filter.covariance()(j, j)));
      });
  // Nothing before the pick-up, and the payload 5 s after it.
  EXPECT_LT(std::abs(before), 0.02 * payload) << before;
  const double weighed = filter.state()[j];
  EXPECT_LT(std::abs(weighed - payload), 0.02 * payload)
      << weighed << " kg weighed +- " << std::sqrt(filter.covariance()(j, j));
}

// A delayed sensor (the chamber pressures' transducers 2 ms late, sampled
// at 100 Hz): its reading, given two steps after it was taken, corrects the
// step it is of, and the filter steps forward again. After each such
// reading, until the next, the filter is the one that had the reading at
// its own time (to the chord Newton's round-off of the consistent rates).
TEST(ExtendedKalmanFilter, ADelayedReadingCorrectsItsOwnStepAsAReadingOnTimeWould) {
  const double t_end = 1.6;
  const ModelFile nominal = fourbar(t_end);
  const ModelFile machine = test::machine_of(nominal);
  Simulation truth(machine, build_plugins());
  Simulation late_run(nominal, build_plugins()), on_time_run(nominal, build_plugins());
  truth.start();
  late_run.start();
  on_time_run.start();
  const FilterNoise noise = tuned_noise(state_variables(late_run));
  std::vector<FilterSensor> sensors = {{"encoder", "z1", 1e-4, 0.0},
                                       {"pA", "p2", kPressureNoise, 0.0},
                                       {"pB", "p3", kPressureNoise, 0.0}};
  ExtendedKalmanFilter on_time(on_time_run, sensors, noise);
  sensors[1].delay = sensors[2].delay = 0.002;
  ExtendedKalmanFilter late(late_run, sensors, noise);
  std::mt19937_64 rng(8);
  std::normal_distribution<double> normal;
  const long steps = std::lround(t_end / nominal.solver.dt);
  std::vector<Eigen::VectorXd> taken;  // each step's readings, as taken
  double worst = 0.0;
  long compared = 0;
  for (long k = 0; k <= steps; ++k) {
    if (k > 0) {
      truth.step();
      on_time.predict();
      late.predict();
    }
    Eigen::VectorXd y(3);
    for (Eigen::Index i = 0; i < 3; ++i)
      y[i] = i > 0 && k % 10 != 0 ? NAN
                                  : test::reading(truth, sensors[static_cast<size_t>(i)]) +
                                        sensors[static_cast<size_t>(i)].noise * normal(rng);
    taken.push_back(y);
    on_time.update(y);
    Eigen::VectorXd arriving = y;  // the pressures of two steps before
    for (Eigen::Index i = 1; i < 3; ++i)
      arriving[i] = k >= 2 ? taken[static_cast<size_t>(k - 2)][i] : NAN;
    late.update(arriving);
    if (k % 10 >= 2 && k >= 10) {
      const Eigen::VectorXd sd = on_time.covariance().diagonal().cwiseSqrt();
      const Eigen::VectorXd off = (late.state() - on_time.state()).cwiseQuotient(sd);
      worst = std::max(worst, off.cwiseAbs().maxCoeff());
      ++compared;
    }
  }
  EXPECT_GT(compared, 1000);
  EXPECT_LT(worst, 1e-3) << "of the on-time filter's standard deviations";
  if (std::getenv("MH_EKF_PRINT") != nullptr) std::printf("worst %.3g sd\n", worst);
}

}  // namespace
}  // namespace mh
