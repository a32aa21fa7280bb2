// The three-simulation test of a state filter (Jaiswal et al. 2022): a
// truth, the hydraulic four-bar with errors in its force model; its
// sensors' readings with seeded white noise; the filter on the nominal
// model. Judged against the nominal model run open loop from the same
// start, and by its own covariance against the errors it actually makes.
// MH_EKF_PRINT=1 prints each run's ratios (docs/estimation.md's table).
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "monohydra/core/extended_kalman_filter.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/state_vector.hpp"
#include "monohydra/core/unscented_kalman_filter.hpp"
#include "test_support.hpp"

namespace mh::test {

inline ModelFile fourbar(double t_end) {
  ModelFile file = load_model_file(source_path("models/fourbar.yaml"));
  file.solver.t_end = t_end;
  return file;
}

inline void set_option(ModelFile& file, const std::string& subsystem, const std::string& key,
                       double value) {
  for (SubsystemSpec& s : file.subsystems)
    if (s.name == subsystem) s.options.at(key).number = value;
}

// The machine: the load's mass +10 %, the cylinder's friction x2
// (efficiency 0.88 -> 0.76), the hoses' bulk modulus -20 %.
inline ModelFile machine_of(ModelFile file) {
  file.model.bodies[2].mass *= 1.10;
  file.model.bodies[2].inertia_B *= 1.10;
  set_option(file, "cylinder", "efficiency", 0.76);
  for (const char* v : {"V1", "V2", "V3"}) set_option(file, v, "bulk_modulus", 0.8 * 550e6);
  return file;
}

// The plant noise the four-bar's filter is tuned with: the error a force
// model 10-20 % off puts on the rates over a second (docs/estimation.md).
inline FilterNoise tuned_noise(const std::vector<LinearVariable>& states) {
  const auto n = static_cast<Eigen::Index>(states.size());
  FilterNoise noise{Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n), Eigen::VectorXd(),
                    Eigen::VectorXd()};
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::string& unit = states[static_cast<size_t>(i)].unit;
    noise.plant[i] = unit == "rad/s" ? 3e-2 : unit == "Pa" ? 1e4 : unit == "V" ? 1e-3 : 0.0;
    noise.initial[i] = unit == "rad/s" ? 1e-3 : unit == "Pa" ? 1e5 : 1e-3;
  }
  return noise;
}

struct Outcome {
  std::vector<std::string> names;
  Eigen::VectorXd filter_rms, open_rms;
  double nees_inside = 0.0;  // the fraction of steps inside the two-sided 95 % band
  double nees_above = 0.0;   // ... above it: the filter overconfident
};

// The truth's reading of each sensor at its rate (steps between samples).
inline double reading(const Simulation& truth, const FilterSensor& s) {
  const std::vector<std::string>& states = truth.state_names();
  for (size_t i = 0; i < states.size(); ++i)
    if (states[i] == s.measures) return truth.states()[static_cast<Eigen::Index>(i)];
  const std::vector<std::string>& outputs = truth.output_names();
  for (size_t i = 0; i < outputs.size(); ++i)
    if (outputs[i] == s.measures) return truth.outputs()[static_cast<Eigen::Index>(i)];
  const std::vector<std::string>& coordinates = truth.coordinate_names();
  for (size_t i = 0; i < coordinates.size(); ++i)
    if (coordinates[i] == s.measures) return truth.z()[static_cast<Eigen::Index>(i)];
  throw std::invalid_argument("no column " + s.measures);
}

inline Outcome three_simulations(const std::vector<FilterSensor>& sensors,
                                 const std::vector<long>& every, double t_end, unsigned seed,
                                 bool unscented = false) {
  const ModelFile nominal = fourbar(t_end);
  const ModelFile machine = machine_of(nominal);
  Simulation truth(machine, build_plugins());
  Simulation open(nominal, build_plugins());
  Simulation estimated(nominal, build_plugins());
  truth.start();
  open.start();
  estimated.start();
  Outcome out;
  const std::vector<LinearVariable> states = state_variables(estimated);
  for (const LinearVariable& v : states) out.names.push_back(v.name);
  std::unique_ptr<StateFilter> made;
  if (unscented)
    made = std::make_unique<UnscentedKalmanFilter>(estimated, sensors, tuned_noise(states));
  else
    made = std::make_unique<ExtendedKalmanFilter>(estimated, sensors, tuned_noise(states));
  StateFilter& filter = *made;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  const auto n = static_cast<Eigen::Index>(states.size());
  out.filter_rms = out.open_rms = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd y(static_cast<Eigen::Index>(sensors.size()));
  const long steps = std::lround(t_end / nominal.solver.dt);
  long inside = 0, above = 0;
  // The two-sided 95 % band of a chi-square of n = 6 degrees of freedom.
  EXPECT_EQ(n, 6);
  const double low = 1.2373, high = 14.4494;
  for (long k = 0; k <= steps; ++k) {
    if (k > 0) {
      truth.step();
      open.step();
      filter.predict();
    }
    for (size_t i = 0; i < sensors.size(); ++i)
      y[static_cast<Eigen::Index>(i)] =
          k % every[i] == 0 ? reading(truth, sensors[i]) + sensors[i].noise * normal(rng) : NAN;
    filter.update(y);
    const Eigen::VectorXd truth_x = state_values(truth);
    const Eigen::VectorXd e = state_values(estimated) - truth_x;
    out.filter_rms += e.cwiseAbs2();
    out.open_rms += (state_values(open) - truth_x).cwiseAbs2();
    const double nees = e.dot(filter.covariance().ldlt().solve(e));
    inside += nees > low && nees < high ? 1 : 0;
    above += nees >= high ? 1 : 0;
  }
  const auto count = static_cast<double>(steps + 1);
  out.filter_rms = (out.filter_rms / count).cwiseSqrt();
  out.open_rms = (out.open_rms / count).cwiseSqrt();
  out.nees_inside = static_cast<double>(inside) / count;
  out.nees_above = static_cast<double>(above) / count;
  if (std::getenv("MH_EKF_PRINT") != nullptr) {
    for (Eigen::Index i = 0; i < n; ++i)
      std::printf("%s %.3f  ", out.names[static_cast<size_t>(i)].c_str(),
                  out.filter_rms[i] / out.open_rms[i]);
    std::printf("inside %.3f above %.3f\n", out.nees_inside, out.nees_above);
  }
  return out;
}

inline const double kPressureNoise = 0.005 * 7.6e6;  // 0.5 % of the supply pressure

// Each state the open-loop model gets wrong, against it: coordinates and
// pressures at most a tenth of the open loop's RMS error (the issue's
// bound); the rate at most a quarter: the encoder's noise sets its floor,
// about 2e-3 rad/s, where the open loop is exact (at rest, before the
// valve opens) and 1e-2 rad/s over the run.
inline void expect_tracks(const Outcome& o) {
  for (size_t i = 0; i < o.names.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    if (o.names[i] == "U") continue;  // the spool: the model's is exact
    const double bound =
        o.names[i].size() > 4 && o.names[i].substr(o.names[i].size() - 4) == "_dot" ? 0.25 : 0.1;
    EXPECT_LT(o.filter_rms[k], bound * o.open_rms[k])
        << o.names[i] << ": filter " << o.filter_rms[k] << ", open loop " << o.open_rms[k];
  }
  // Consistent: the error normalised by the filter's own covariance is
  // above the chi-square band's upper end (the filter sure of a state it
  // has wrong) in under 10 % of the steps (2.4 to 5.7 % measured).
  EXPECT_LT(o.nees_above, 0.1);
}

// The crank's encoder and both chamber pressures, as the tests read them.
inline std::vector<FilterSensor> encoder_and_pressures() {
  return {{"encoder", "z1", 1e-4, 0.0},
          {"pA", "p2", kPressureNoise, 0.0},
          {"pB", "p3", kPressureNoise, 0.0}};
}

// Steps 0 .. steps: the truth and the filter stepped together (from step
// 1), the filter updated with every sensor's reading of the truth plus
// white noise of its level (seed `seed`). `before(step)` first at each step
// (the machine changed there), `after(step)` after its update.
inline void filter_along(
    Simulation& truth, StateFilter& filter, long steps, unsigned seed,
    const std::function<void(long)>& before = [](long) {},
    const std::function<void(long)>& after = [](long) {}) {
  const std::vector<FilterSensor>& sensors = filter.sensors();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::VectorXd y(static_cast<Eigen::Index>(sensors.size()));
  for (long k = 0; k <= steps; ++k) {
    before(k);
    if (k > 0) {
      truth.step();
      filter.predict();
    }
    for (Eigen::Index i = 0; i < y.size(); ++i)
      y[i] = reading(truth, sensors[static_cast<size_t>(i)]) +
             sensors[static_cast<size_t>(i)].noise * normal(rng);
    filter.update(y);
    after(k);
  }
}

}  // namespace mh::test
