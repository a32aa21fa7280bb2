// The monohydra command line's subcommands.
#pragma once

#include <string>
#include <vector>

namespace mh::cli {

// Each returns the process exit code: 0 success, 1 the simulation failed
// (results up to the failure are kept), 2 bad usage or bad input.
int plugins(const std::vector<std::string>& args);
int run(const std::vector<std::string>& args);
int compare(const std::vector<std::string>& args);  // compare.cpp
int run_default();                                  // default_job.cpp
int usage(int code);

}  // namespace mh::cli
