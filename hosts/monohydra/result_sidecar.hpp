// NAME.meta.json beside every result file: what produced it (monohydra's
// version, each plugin's library and version, the model file's SHA-256, the
// command line) and the settings the run actually used, so that any result
// can be traced and run again.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "model_plugins.hpp"
#include "model_settings.hpp"
#include "monohydra/core/model_file.hpp"

namespace mh::cli {

struct ResultProvenance {
  std::string model_path;  // as given on the command line
  std::string formulation, integrator;
  SolverSettings solver;                  // with the dt and t_end the run used
  std::optional<double> output_interval;  // --output-interval, when given
  int real_time_cap = 0;                  // --real-time's Newton cap (0: off)
  std::vector<host::UsedComponent> plugins;
  std::vector<host::PathSetting> set;             // --set PATH=VALUE, in order
  std::optional<unsigned long long> sensor_seed;  // --sensors-out's file: its noise's seed
  // An explicit integrator's stability check, once the run has made it
  // (null, or no checks: "explicit_stability": null).
  const ExplicitStability* stability = nullptr;
};

// The sidecar's path: `result` with its extension replaced by .meta.json.
std::string sidecar_path(const std::string& result);

// The lowercase hex SHA-256 of a file's bytes; "" when it cannot be read.
std::string file_sha256(const std::string& path);

// Writes the sidecar of `result`; false (and why on stderr) when it cannot.
bool write_sidecar(const std::string& result, const ResultProvenance& p);

}  // namespace mh::cli
