// A study file (docs/sweeps.md): the base models, the values to vary and how
// to combine them, fixed settings, reference runs, the metrics kept per case
// and the report's plots. Every problem is an InputError naming the study
// file, line and field.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "monohydra/core/input_error.hpp"

namespace mh::cli::sweep {

struct BaseModel {
  std::string name;  // the `model` column
  std::string path;  // resolved against the study file's folder
  YAML::Node tree;   // the file as read, before any override
};

// How a parameter's values are given (case_expansion.cpp turns them into values).
struct ParameterSpec {
  std::string path;  // normalized model path, e.g. subsystems/valve/flow_coefficient
  SourceMark mark;
  YAML::Node
      values;  // a list, a range {from, to, count|step, scale}, or a draw {distribution, ...}
};

// One value a case gives a parameter: the YAML scalar it sets and its text
// in the table.
using Overrides = std::vector<std::pair<std::string, YAML::Node>>;

struct MetricSpec {
  // peak_drift, drift_percent, max_phi_norm, newton_iterations, mean_iterations,
  // steps, max, min, final, error
  std::string kind;
  std::string column;     // for max/min/final/error
  std::string reference;  // for error
  std::string header;     // its column in results.csv
  SourceMark mark;
};

struct PlotRequest {
  std::string x, y;  // results.csv columns (parameters or metrics)
  bool log_x = false, log_y = false;
  std::string title;
  std::string model;  // only this model's rows ("" every model's)
  SourceMark mark;
};

struct Study {
  std::string path;  // the study file as given
  std::string name;
  std::vector<BaseModel> models;
  Overrides set;  // fixed overrides of every case (below --dt/--t-end)
  std::vector<ParameterSpec> parameters;
  std::string combine = "factorial";  // or "zip"
  std::vector<Overrides> listed;      // `cases:`: the listed combinations
  std::vector<std::string> listed_paths;
  std::uint64_t seed = 1;
  std::map<std::string, Overrides> references;  // name -> overrides of the base model
  std::vector<MetricSpec> metrics;
  std::vector<PlotRequest> plots;
};

// Reads and checks the study file: every path exists in every base model,
// every metric and reference is known. Throws InputError.
Study load_study(const std::string& path);

}  // namespace mh::cli::sweep
