// The C API's estimator (simulation.h, 1.4): a Kalman filter of the core
// (extended or unscented) on the run of its handle, set up from the model
// file's sensors and the filters' default noise (filter_defaults.hpp) as
// `monohydra estimate` sets it up, so that the same data give the same
// estimates from either.
#include <cmath>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "api_handle.hpp"
#include "instance.hpp"
#include "monohydra/core/extended_kalman_filter.hpp"
#include "monohydra/core/filter_defaults.hpp"
#include "monohydra/core/state_vector.hpp"
#include "monohydra/core/unscented_kalman_filter.hpp"
#include "monohydra/cpp/number_text.hpp"
#include "monohydra/simulation.h"

using mh::embed::ensure_started;
using mh::embed::guarded;
using mh::embed::Instance;
using mh::embed::refuse;

struct mhs_estimator {
  const mhs_simulation* sim = nullptr;  // the run it drives
  std::unique_ptr<mh::StateFilter> filter;
  std::string failure;  // why the filter stopped ("": it did not)
  // Where it left the run: its step and state. A run stepped or restored
  // since by another call is not the one its covariance describes.
  long step = 0;
  Eigen::VectorXd x;
};

namespace {

using monohydra::short_number;

// `est` made on `sim`, or why not.
std::string mismatch(const mhs_simulation* sim, const mhs_estimator* est, const char* call) {
  if (est == nullptr) return std::string(call) + ": the estimator is NULL";
  if (est->sim != sim) return std::string(call) + ": the estimator was made on another run";
  return "";
}

// The run where the estimator left it, or why not (another call moved it).
std::string moved(const mh::Simulation& s, const mhs_estimator* est, const char* call) {
  if (s.step_index() == est->step && mh::state_values(s) == est->x) return "";
  return std::string(call) + ": the run was moved since the estimator's last call (by mhs_step, " +
         "mhs_advance, mhs_restore or a setting of its state: now at t = " +
         short_number(s.time()) +
         " s): the filter's covariance is of the state it left; leave the run to the "
         "estimator, or make a new one";
}

void leave(const mh::Simulation& s, mhs_estimator* est) {
  est->step = s.step_index();
  est->x = mh::state_values(s);
}

// The noise the options set over the defaults; "" or why not.
std::string apply_noise(const mhs_estimator_options& o,
                        const std::vector<mh::LinearVariable>& states,
                        const std::vector<mh::ParameterDirection>& params, mh::FilterNoise& noise) {
  if (o.noise_count > 0 && o.noise_names == nullptr)
    return "noise_names is NULL with a noise_count of " + std::to_string(o.noise_count);
  for (size_t i = 0; i < o.noise_count; ++i) {
    if (o.noise_names[i] == nullptr) return "noise_names[" + std::to_string(i) + "] is NULL";
    const std::string name = o.noise_names[i];
    double* plant = nullptr;
    double* initial = nullptr;
    for (size_t s = 0; s < states.size() && plant == nullptr; ++s)
      if (states[s].name == name) {
        plant = &noise.plant[static_cast<Eigen::Index>(s)];
        initial = &noise.initial[static_cast<Eigen::Index>(s)];
      }
    for (size_t j = 0; j < params.size() && plant == nullptr; ++j)
      if (params[j].path == name) {
        plant = &noise.parameter_plant[static_cast<Eigen::Index>(j)];
        initial = &noise.parameter_initial[static_cast<Eigen::Index>(j)];
      }
    if (plant == nullptr) {
      std::string known;
      for (const mh::LinearVariable& v : states) known += (known.empty() ? "" : ", ") + v.name;
      for (const mh::ParameterDirection& p : params) known += ", " + p.path;
      return "noise_names[" + std::to_string(i) + "] = '" + name +
             "' is not a state or parameter of the filter (" + known + ")";
    }
    for (const auto& [given, into, what] :
         {std::tuple<const double*, double*, const char*>{o.plant_sd, plant, "plant_sd"},
          {o.initial_sd, initial, "initial_sd"}}) {
      if (given == nullptr) continue;
      const double v = given[i];
      if (std::isnan(v)) continue;
      if (!(v >= 0.0) || !std::isfinite(v))
        return std::string(what) + "[" + std::to_string(i) + "] (" + name +
               ") = " + short_number(v) + ": expected a standard deviation of 0 or more";
      *into = v;
    }
  }
  return "";
}

}  // namespace

extern "C" {

MHS_API mhs_status mhs_estimator_new(mhs_simulation* sim, const mhs_estimator_options* options,
                                     mhs_estimator** out) {
  if (out != nullptr) *out = nullptr;
  return guarded(sim, [&](Instance& in) -> mhs_status {
    if (out == nullptr) return refuse(sim, "mhs_estimator_new: out is NULL");
    mhs_estimator_options o{};
    if (options != nullptr) {
      if (options->struct_size < sizeof(mhs_estimator_options))
        return refuse(sim, "mhs_estimator_new: options->struct_size is " +
                               std::to_string(options->struct_size) + ", at least " +
                               std::to_string(sizeof(mhs_estimator_options)) + " expected");
      o = *options;
    }
    const std::string kind = o.filter == nullptr ? "ekf" : o.filter;
    if (kind != "ekf" && kind != "ukf")
      return refuse(sim, "mhs_estimator_new: filter '" + kind + "': expected ekf or ukf");
    if (!sim->failure.empty())
      return refuse(sim, "mhs_estimator_new: the run's last step failed (" + sim->failure +
                             "); restore a snapshot (mhs_restore) first");
    const mh::ModelFile& file = in.file();
    if (file.sensors.empty())
      return refuse(sim, "mhs_estimator_new: " + in.label() +
                             " has no sensors: add a sensors: list to the model");
    std::vector<mh::FilterSensor> sensors;
    std::vector<mh::ParameterDirection> params;
    try {
      for (const mh::SensorSpec& s : file.sensors)
        sensors.push_back(mh::filter_sensor(s, in.label()));
      if (o.param_count > 0 && o.params == nullptr)
        return refuse(sim, "mhs_estimator_new: params is NULL with a param_count of " +
                               std::to_string(o.param_count));
      for (size_t j = 0; j < o.param_count; ++j) {
        if (o.params[j] == nullptr)
          return refuse(sim, "mhs_estimator_new: params[" + std::to_string(j) + "] is NULL");
        params.push_back(in.parameter(o.params[j]));
      }
    } catch (const std::invalid_argument& err) {
      return refuse(sim, std::string("mhs_estimator_new: ") + err.what());
    }
    ensure_started(sim, in);
    const std::vector<mh::LinearVariable> states = mh::state_variables(in.sim());
    mh::FilterNoise noise = mh::default_filter_noise(states, params);
    const std::string why = apply_noise(o, states, params, noise);
    if (!why.empty()) return refuse(sim, "mhs_estimator_new: " + why);
    auto est = std::make_unique<mhs_estimator>();
    est->sim = sim;
    try {
      if (kind == "ukf")
        est->filter = std::make_unique<mh::UnscentedKalmanFilter>(in.sim(), sensors, noise, params);
      else
        est->filter = std::make_unique<mh::ExtendedKalmanFilter>(in.sim(), sensors, noise, params);
    } catch (const std::invalid_argument& err) {
      return refuse(sim, std::string("mhs_estimator_new: ") + err.what());
    }
    leave(in.sim(), est.get());
    *out = est.release();
    return MHS_OK;
  });
}

MHS_API void mhs_estimator_free(mhs_estimator* est) {
  delete est;
}

MHS_API mhs_status mhs_estimator_size(mhs_simulation* sim, const mhs_estimator* est,
                                      uint32_t* states, uint32_t* sensors) {
  return guarded(sim, [&](Instance&) -> mhs_status {
    const std::string wrong = mismatch(sim, est, "mhs_estimator_size");
    if (!wrong.empty()) return refuse(sim, wrong);
    if (states != nullptr) *states = static_cast<uint32_t>(est->filter->states().size());
    if (sensors != nullptr) *sensors = static_cast<uint32_t>(est->filter->sensors().size());
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_estimator_name(mhs_simulation* sim, const mhs_estimator* est,
                                      mhs_estimator_role role, uint32_t k, const char** name,
                                      const char** unit) {
  return guarded(sim, [&](Instance& in) -> mhs_status {
    const std::string wrong = mismatch(sim, est, "mhs_estimator_name");
    if (!wrong.empty()) return refuse(sim, wrong);
    const auto& states = est->filter->states();
    const auto& sensors = est->filter->sensors();
    if (role == MHS_ESTIMATOR_STATE) {
      if (k >= states.size())
        return refuse(sim, "mhs_estimator_name: state " + std::to_string(k) + " is not below " +
                               std::to_string(states.size()));
      if (name != nullptr) *name = states[k].name.c_str();
      if (unit != nullptr) *unit = states[k].unit.c_str();
      return MHS_OK;
    }
    if (role != MHS_ESTIMATOR_SENSOR)
      return refuse(sim, "mhs_estimator_name: role " + std::to_string(role) +
                             " is neither MHS_ESTIMATOR_STATE nor MHS_ESTIMATOR_SENSOR");
    if (k >= sensors.size())
      return refuse(sim, "mhs_estimator_name: sensor " + std::to_string(k) + " is not below " +
                             std::to_string(sensors.size()));
    if (name != nullptr) *name = sensors[k].name.c_str();
    if (unit != nullptr) {
      // The unit of the column it measures.
      *unit = "";
      for (const mh::embed::Variable& v : in.variables())
        if (v.name == sensors[k].measures || v.qualified == sensors[k].measures) {
          *unit = v.unit.c_str();
          break;
        }
    }
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_estimator_update(mhs_simulation* sim, mhs_estimator* est, double t,
                                        const double* readings, size_t count) {
  return guarded(sim, [&](Instance& in) -> mhs_status {
    const std::string wrong = mismatch(sim, est, "mhs_estimator_update");
    if (!wrong.empty()) return refuse(sim, wrong);
    if (!est->failure.empty())
      return refuse(sim, "mhs_estimator_update: the filter stopped (" + est->failure +
                             "); make a new estimator");
    if (!sim->failure.empty())
      return refuse(sim, "mhs_estimator_update: the run's last step failed (" + sim->failure + ")");
    const std::string elsewhere = moved(in.sim(), est, "mhs_estimator_update");
    if (!elsewhere.empty()) return refuse(sim, elsewhere);
    mh::StateFilter& f = *est->filter;
    if (count != f.sensors().size())
      return refuse(sim, "mhs_estimator_update: " + std::to_string(count) +
                             " readings for the filter's " + std::to_string(f.sensors().size()) +
                             " sensors");
    if (count > 0 && readings == nullptr)
      return refuse(sim, "mhs_estimator_update: readings is NULL");
    if (!std::isfinite(t))
      return refuse(sim, "mhs_estimator_update: t = " + short_number(t) + " is not a finite time");
    mh::Simulation& s = in.sim();
    const double dt = s.settings().dt;
    const long target = std::lround(t / dt);
    if (target < s.step_index())
      return refuse(sim, "mhs_estimator_update: t = " + short_number(t) +
                             " s falls before the run's step at " + short_number(s.time()) + " s");
    const Eigen::Map<const Eigen::VectorXd> values(readings, static_cast<Eigen::Index>(count));
    for (size_t c = 0; c < count; ++c)
      if (std::isinf(readings[c]))
        return refuse(sim, "mhs_estimator_update: sensor '" + f.sensors()[c].name + "': reading " +
                               short_number(readings[c]) +
                               " (NaN is no sample; an infinite reading is refused)");
    try {
      while (s.step_index() < target) {
        try {
          f.predict();
        } catch (const mh::SimulationError& err) {
          sim->failure = err.what();
          throw;
        }
      }
      f.update(values);
    } catch (const mh::SimulationError& err) {
      est->failure = err.what();
      return refuse(sim, est->failure);
    }
    leave(s, est);
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_estimator_state(mhs_simulation* sim, const mhs_estimator* est, double* x,
                                       double* covariance, size_t n) {
  return guarded(sim, [&](Instance& in) -> mhs_status {
    const std::string wrong = mismatch(sim, est, "mhs_estimator_state");
    if (!wrong.empty()) return refuse(sim, wrong);
    const std::string elsewhere = moved(in.sim(), est, "mhs_estimator_state");
    if (!elsewhere.empty()) return refuse(sim, elsewhere);
    const mh::StateFilter& f = *est->filter;
    const size_t states = f.states().size();
    if (n != states)
      return refuse(sim, "mhs_estimator_state: n = " + std::to_string(n) + ", the filter has " +
                             std::to_string(states) + " states");
    if (x == nullptr) return refuse(sim, "mhs_estimator_state: x is NULL");
    const Eigen::VectorXd v = f.state();
    Eigen::Map<Eigen::VectorXd>(x, v.size()) = v;
    if (covariance != nullptr)
      Eigen::Map<Eigen::MatrixXd>(covariance, v.size(), v.size()) = f.covariance();
    return MHS_OK;
  });
}

MHS_API mhs_status mhs_estimator_innovations(mhs_simulation* sim, const mhs_estimator* est,
                                             double* innovation, double* sd, size_t count,
                                             double* nis) {
  return guarded(sim, [&](Instance&) -> mhs_status {
    const std::string wrong = mismatch(sim, est, "mhs_estimator_innovations");
    if (!wrong.empty()) return refuse(sim, wrong);
    const mh::StateFilter& f = *est->filter;
    if ((innovation != nullptr || sd != nullptr) && count != f.sensors().size())
      return refuse(sim, "mhs_estimator_innovations: count = " + std::to_string(count) +
                             ", the filter has " + std::to_string(f.sensors().size()) + " sensors");
    const bool none = f.samples() == 0;  // no update yet, or one without a sample
    for (size_t c = 0; c < count; ++c) {
      const auto i = static_cast<Eigen::Index>(c);
      if (innovation != nullptr) innovation[c] = none ? NAN : f.innovation()[i];
      if (sd != nullptr) sd[c] = none ? NAN : f.innovation_sd()[i];
    }
    if (nis != nullptr) *nis = none ? NAN : f.nis();
    return MHS_OK;
  });
}

}  // extern "C"
