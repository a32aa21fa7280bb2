// The model as `fit` sees it: one run at given parameter values, read where
// the data were sampled. Each measured column is a result column `run`
// writes (a coordinate, a named state, a differentiated output) or a sensor
// of the model's sensors: (read through its delay and bias); the model's
// value at a sample's time is interpolated linearly between the two steps
// around it, and so is its sensitivity, so that the Jacobian is the exact
// derivative of the prediction.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "measured_data.hpp"
#include "run_setup.hpp"
#include "sensitivity_columns.hpp"

namespace mh::cli {

// One measured value: column c of the data at its row i.
struct Sample {
  size_t column = 0;
  size_t row = 0;
};

// What a measured column reads of the model.
struct MeasuredColumn {
  std::string name;      // the data's
  std::string measures;  // the result column
  double delay = 0.0, bias = 0.0;
  double noise = 0.0;  // the sensor's standard deviation; 0: none declared
};

class SampledRun {
 public:
  // Checks everything before any fit: the model opens as `run` would with
  // `request` (its --set values), every path is a parameter the file writes
  // a number at, every data column is one the model has, and the run reaches
  // the last sample (without --t-end, it ends at the last sample's step),
  // and every initial value is inside its range.
  // Throws InputError (the data's file, line and column; the model's) or
  // std::invalid_argument (a path: the path first).
  SampledRun(const RunRequest& request, const std::vector<std::string>& paths,
             const MeasuredData& data);

  const std::vector<std::string>& paths() const { return paths_; }
  const Eigen::VectorXd& initial() const { return initial_; }  // as the file writes them
  // The values each parameter takes (a mass above 0, a component's declared
  // range; +-infinity: no bound).
  const Eigen::VectorXd& lower() const { return lower_; }
  const Eigen::VectorXd& upper() const { return upper_; }
  const std::vector<MeasuredColumn>& columns() const { return columns_; }
  const std::vector<Sample>& samples() const { return samples_; }
  const Eigen::VectorXd& measured() const { return measured_; }  // one per sample
  // The settings that make the model file the model at `p` (its --set and the paths').
  std::vector<host::PathSetting> settings_at(const Eigen::VectorXd& p) const;

  // The model at parameter values `p`: its prediction of every sample and,
  // when `J` is given, d prediction / d p (one column per path). False, with
  // the reason in `why`, when the model refuses the values or the run stops.
  bool evaluate(const Eigen::VectorXd& p, Eigen::VectorXd& predicted, Eigen::MatrixXd* J,
                std::string& why) const;

 private:
  RunRequest request_;
  std::vector<std::string> paths_;
  Eigen::VectorXd initial_, lower_, upper_;
  std::vector<MeasuredColumn> columns_;
  // Where each is in the model's results: the same in every run of it, at
  // any values (a run without sensitivities would not say which outputs
  // have them).
  std::vector<SensitivityColumn> read_;
  std::vector<Sample> samples_;  // in time order
  std::vector<double> times_;    // each sample's time in the model (less its delay)
  Eigen::VectorXd measured_;
  double t_end_ = 0.0;
};

}  // namespace mh::cli
