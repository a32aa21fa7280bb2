#include "sampled_run.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "model_settings.hpp"
#include "monohydra/core/input_error.hpp"
#include "monohydra/core/model_text.hpp"
#include "monohydra/cpp/number_text.hpp"
#include "parameter_path.hpp"
#include "sensitivity_columns.hpp"

namespace mh::cli {

namespace {

// The run for `request`, or std::runtime_error after prepare_run told why.
std::unique_ptr<PreparedRun> open_run(const RunRequest& request) {
  auto prepared = prepare_run(request);
  if (!prepared) throw std::runtime_error("the model does not open with these values (above)");
  return prepared;
}

std::string list_of(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

}  // namespace

SampledRun::SampledRun(const RunRequest& request, const std::vector<std::string>& paths,
                       const MeasuredData& data)
    : request_(request), paths_(paths) {
  // The initial values: the numbers the file (with its --set values) writes.
  std::string text = read_model_text(request.model_path);
  if (!request.overrides.set.empty())
    text = host::apply_settings(text, request.model_path, request.overrides.set).text;
  const YAML::Node root = YAML::Load(text);
  initial_.resize(static_cast<Eigen::Index>(paths.size()));
  for (size_t j = 0; j < paths.size(); ++j) {
    const std::optional<YAML::Node> node = host::value_at(root, paths[j]);
    double v = 0.0;
    if (!node || !node->IsScalar() || !YAML::convert<double>::decode(*node, v) || !std::isfinite(v))
      throw std::invalid_argument(paths[j] +
                                  ": the model file writes no number there, and a fit starts "
                                  "from the number the file writes (write one, or give it "
                                  "with --set " +
                                  paths[j] + "=VALUE)");
    initial_(static_cast<Eigen::Index>(j)) = v;
  }

  const auto prepared = open_run(request);
  Simulation& sim = *prepared->sim;
  // The paths as parameters: refused here, before any fit, as tracking refuses them.
  const std::vector<ParameterDirection> directions =
      parameter_directions(request, prepared->file, paths);
  sim.track_sensitivities(directions);
  const double inf = std::numeric_limits<double>::infinity();
  lower_ = Eigen::VectorXd::Constant(initial_.size(), -inf);
  upper_ = Eigen::VectorXd::Constant(initial_.size(), inf);
  for (size_t j = 0; j < paths.size(); ++j) {
    const auto i = static_cast<Eigen::Index>(j);
    const std::vector<std::string> segments = host::split_path(paths[j]);
    std::string unit;
    if (!directions[j].subsystem.empty()) {
      const Simulation::ParameterRange range =
          sim.component_parameter_range(directions[j].subsystem, directions[j].key);
      lower_(i) = range.lower;
      upper_(i) = range.upper;
      unit = " " + range.unit;
    } else if (segments.front() == "bodies" && segments.back() == "mass") {
      lower_(i) = 0.0;
    }
    if (!(initial_(i) >= lower_(i) && initial_(i) <= upper_(i)))
      throw std::invalid_argument(paths[j] + ": " + monohydra::short_number(initial_(i)) +
                                  " is outside its range [" + monohydra::short_number(lower_(i)) +
                                  ", " + monohydra::short_number(upper_(i)) + "]" + unit);
  }

  std::vector<std::string> model_names, sensor_names;
  const std::vector<SensitivityColumn> model = sensitivity_columns(sim);
  for (const SensitivityColumn& c : model) model_names.push_back(c.name);
  for (const SensorSpec& s : prepared->file.sensors) sensor_names.push_back(s.name);
  for (size_t c = 0; c < data.names.size(); ++c) {
    MeasuredColumn column{data.names[c], data.names[c]};
    for (const SensorSpec& s : prepared->file.sensors)
      if (s.name == data.names[c]) {
        column.measures = s.measures;
        column.delay = s.delay;
        column.bias = s.bias;
        column.noise = s.noise;
      }
    if (std::find(model_names.begin(), model_names.end(), column.measures) == model_names.end())
      throw InputError({data.path, 1, static_cast<int>(c + 2)}, data.names[c],
                       "a column of the model's that carries sensitivities (" +
                           list_of(model_names) + ") or one of its sensors (" +
                           list_of(sensor_names) + ")");
    columns_.push_back(column);
    read_.push_back(model[static_cast<size_t>(
        std::find(model_names.begin(), model_names.end(), column.measures) - model_names.begin())]);
  }

  // The samples, in the order of their time in the model (less each delay).
  std::vector<Sample> all;
  std::vector<double> when;
  for (size_t i = 0; i < data.t.size(); ++i)
    for (size_t c = 0; c < data.names.size(); ++c)
      if (!std::isnan(data.values[c][i])) {
        all.push_back({c, i});
        when.push_back(std::max(0.0, data.t[i] - columns_[c].delay));
      }
  if (data.t.front() < 0.0)
    throw InputError(
        {data.path, 2, 1}, "t",
        "times from 0 on (the run's start), not " + monohydra::short_number(data.t.front()));
  std::vector<size_t> order(all.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return when[a] < when[b]; });
  measured_.resize(static_cast<Eigen::Index>(all.size()));
  for (size_t s = 0; s < order.size(); ++s) {
    const Sample& sample = all[order[s]];
    samples_.push_back(sample);
    times_.push_back(when[order[s]]);
    measured_(static_cast<Eigen::Index>(s)) = data.values[sample.column][sample.row];
  }

  // The run ends at --t-end, or at the step of the last sample.
  const double dt = sim.settings().dt;
  const double last = times_.empty() ? 0.0 : times_.back();
  if (request.overrides.t_end) {
    t_end_ = *request.overrides.t_end;
    if (last > t_end_ + 1e-9 * dt)
      throw InputError({data.path, 0, 1}, "t",
                       "samples up to the run's end, --t-end " + monohydra::short_number(t_end_) +
                           " s; the last is at " + monohydra::short_number(last) + " s");
  } else {
    t_end_ = std::max(1.0, std::ceil(last / dt - 1e-9)) * dt;
  }
}

std::vector<host::PathSetting> SampledRun::settings_at(const Eigen::VectorXd& p) const {
  std::vector<host::PathSetting> settings = request_.overrides.set;
  for (size_t j = 0; j < paths_.size(); ++j)
    settings.push_back({paths_[j], monohydra::exact_number(p(static_cast<Eigen::Index>(j)))});
  return settings;
}

bool SampledRun::evaluate(const Eigen::VectorXd& p, Eigen::VectorXd& predicted, Eigen::MatrixXd* J,
                          std::string& why) const {
  RunRequest request = request_;
  request.overrides.set = settings_at(p);
  request.overrides.t_end = t_end_;
  try {
    const auto prepared = open_run(request);
    Simulation& sim = *prepared->sim;
    const auto k = static_cast<Eigen::Index>(paths_.size());
    if (J != nullptr) {
      sim.track_sensitivities(parameter_directions(request, prepared->file, paths_));
      J->setZero(static_cast<Eigen::Index>(samples_.size()), k);
    }
    predicted.resize(static_cast<Eigen::Index>(samples_.size()));
    const std::vector<SensitivityColumn>& read = read_;
    const auto m = static_cast<Eigen::Index>(read.size());
    Eigen::VectorXd before(m), now(m);
    Eigen::MatrixXd before_d = Eigen::MatrixXd::Zero(m, k), now_d = before_d;
    const auto take = [&] {
      for (Eigen::Index c = 0; c < m; ++c) {
        now(c) = column_value(sim, read[static_cast<size_t>(c)]);
        if (J != nullptr)
          for (Eigen::Index j = 0; j < k; ++j)
            now_d(c, j) =
                column_sensitivity(sim, read[static_cast<size_t>(c)], static_cast<int>(j));
      }
    };
    sim.start();
    take();
    double t_before = sim.time();
    size_t next = 0;
    const double dt = sim.settings().dt;
    const auto assign = [&](bool first) {
      const double t_now = sim.time();
      for (; next < samples_.size() && times_[next] <= t_now + 1e-9 * dt; ++next) {
        const double w =
            first ? 1.0 : std::clamp((times_[next] - t_before) / (t_now - t_before), 0.0, 1.0);
        const auto s = static_cast<Eigen::Index>(next);
        const auto c = static_cast<Eigen::Index>(samples_[next].column);
        predicted(s) = (1.0 - w) * before(c) + w * now(c) + columns_[samples_[next].column].bias;
        if (J != nullptr) J->row(s) = (1.0 - w) * before_d.row(c) + w * now_d.row(c);
      }
    };
    assign(true);
    for (long n = 0; n < prepared->steps && next < samples_.size(); ++n) {
      before = now;
      before_d = now_d;
      t_before = sim.time();
      sim.step();
      take();
      assign(false);
    }
    if (next < samples_.size()) {
      why = "the run ended at t = " + monohydra::short_number(sim.time()) +
            " s before the sample at " + monohydra::short_number(times_[next]) + " s";
      return false;
    }
  } catch (const std::exception& err) {
    why = err.what();
    return false;
  }
  return true;
}

}  // namespace mh::cli
