// The monohydra command line's subcommands.
#pragma once

#include <string>
#include <vector>

namespace mh::cli {

// Each returns the process exit code: 0 success, 1 the simulation failed or its
// results could not be written (results up to there are kept), 2 bad usage or
// bad input, 128 + N stopped by signal N (130 SIGINT, 143 SIGTERM).
int plugins(const std::vector<std::string>& args);
int run(const std::vector<std::string>& args);
int validate(const std::vector<std::string>& args);       // 0 OK, 1 the error, 2 bad usage
int compare(const std::vector<std::string>& args);        // compare.cpp
int linearize(const std::vector<std::string>& args);      // linearize_command.cpp
int sensitivities(const std::vector<std::string>& args);  // sensitivities_command.cpp
int fit(const std::vector<std::string>& args);            // fit_command.cpp
int estimate(const std::vector<std::string>& args);       // estimate/estimate_command.cpp
int fmu(const std::vector<std::string>& args);            // fmu_command.cpp
int forces(const std::vector<std::string>& args);         // forces_command.cpp
int run_default();                                        // default_job.cpp
int usage(int code);

}  // namespace mh::cli
