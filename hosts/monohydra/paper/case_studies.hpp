// The paper's case studies and what the paper reports for them, read from a
// small YAML file (models/paper-reference.yaml): the default job runs each one
// and sets the paper's numbers beside ours. Format: docs/compare.md.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "monohydra/core/model_file.hpp"

namespace mh::cli {

// What the paper reports for one formulation on one case study.
struct PaperRun {
  std::string formulation;
  std::string coordinates;  // the coordinates in use it reports (e.g. independent ones), or ""
  std::optional<double> avg_iterations;
  std::optional<double> max_iterations;
  std::optional<double> total_seconds;  // total integration time, on the paper's platform
};

// What the paper reports for one case study (absent numbers stay empty).
struct PaperNumbers {
  std::string source;                        // where the numbers come from, e.g. "Sect. 6"
  std::string platform;                      // where the paper's times were measured
  std::string integrator;                    // the integrator the paper used: its numbers
                                             // stand beside our runs with that one only
  std::optional<double> max_actuator_work;   // J
  std::optional<double> peak_drift;          // J
  std::optional<double> peak_drift_percent;  // % of the maximum actuator work
  std::optional<double> peak_drift_time;     // s
  std::vector<PaperRun> runs;

  // Null when absent, or when `integrator` is not the paper's.
  const PaperRun* run(const std::string& formulation, const std::string& integrator) const;
};

struct CaseStudy {
  std::string name;                       // e.g. "four-bar"
  std::string model_path;                 // resolved against the reference file's folder
  std::string report_dir;                 // as written: relative to the working directory
  std::vector<std::string> formulations;  // compared, in order
  std::string control_shading;  // "#rrggbb": the paper's colour where a control signal is on
  // The paper's Newton (its Newton-Raphson factors a tangent at every
  // iteration), in place of the model file's: its iteration counts stand
  // beside ours. Unset: the model file's.
  std::optional<NewtonKind> newton;
  PaperNumbers paper;
};

// The case-study file in use: $MONOHYDRA_CASE_STUDIES when set (for tests,
// until the hydraulic models exist), else the shipped paper-reference.yaml.
std::string case_studies_path();

// Reads the case studies. Throws InputError naming the file, line and field.
std::vector<CaseStudy> load_case_studies(const std::string& path);

// The case study whose model is the file at `model_path` (same file on disk),
// or null.
const CaseStudy* find_case_study(const std::vector<CaseStudy>& studies,
                                 const std::string& model_path);

}  // namespace mh::cli
