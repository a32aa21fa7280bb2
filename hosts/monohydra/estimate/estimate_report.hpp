// `estimate --report DIR`: what each filter made of the same recorded data,
// beside the model run open loop and, with --truth, the machine's own run:
// the estimates with their 2-sigma bands, the sensors' readings against the
// filters' predictions of them, and with the truth each state's RMS error
// and how often the truth lies inside the filter's band, and the normalised
// estimation error squared against its chi-square band (docs/estimation.md).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "measured_data.hpp"

namespace mh::cli {

// One run over the data, a row per step.
struct FilterTrack {
  std::string label;             // "ekf", "ukf", "open loop"
  double cpu_seconds = 0.0;      // of the run, the start included
  std::vector<double> t;         // s
  Eigen::MatrixXd estimate, sd;  // steps x states (sd: none for the open loop)
  Eigen::MatrixXd predicted;     // steps x sensors: the reading the filter expected (NaN: none)
  std::vector<double> nees;      // per step, over the states the truth has (NaN: no truth row)
};

struct EstimateReport {
  std::string model, data_path, truth_path;
  std::vector<std::string> states, units;  // the filters' states (and parameters)
  std::vector<std::string> sensors;
  Eigen::MatrixXd measured;          // steps x sensors (NaN: no sample)
  std::vector<FilterTrack> filters;  // the open loop first
  // With --truth: each state's column of it (-1: none), and its values per step.
  std::vector<int> truth_column;
  Eigen::MatrixXd truth;  // steps x states (NaN where the truth has no row or column)
  int nees_dof = 0;       // the states the truth has
};

// The truth's value of every state at every step t_k (the row at the
// step's time, within half a step; NaN without one). Throws
// std::invalid_argument when the truth names none of the states.
void attach_truth(EstimateReport& report, const MeasuredData& truth, double dt);

// e^T P^-1 e over the states the truth has, at step k (NaN without a row).
double nees_at(const EstimateReport& report, Eigen::Index k, const Eigen::VectorXd& estimate,
               const Eigen::MatrixXd& covariance);

std::string estimate_report_html(const EstimateReport& report);

}  // namespace mh::cli
