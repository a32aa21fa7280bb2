// What the subcommands share: number and limit arguments, the log sink that prints a
// plugin's warnings and errors, and the progress bar on a terminal.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "monohydra/core/explicit_stability.hpp"
#include "monohydra/core/run_limits.hpp"
#include "monohydra/types.h"

namespace mh::cli {

// The number in `text`, or nullopt after telling the user that `flag` expects one.
// --explicit-stability's value: error, warn or off; nullopt after saying what is wrong.
std::optional<ExplicitStabilityPolicy> parse_stability_option(const std::string& text);

std::optional<double> parse_number(const std::string& flag, const std::string& text);
// A comma-separated list's non-empty items, in order ("a,,b" is {a, b}).
std::vector<std::string> split_list(const std::string& list);

// --max-steps N or --max-output-bytes N into `limits`; false after telling the user.
bool parse_limit(const std::string& flag, const std::string& text, RunLimits& limits);

// After a failed write: cuts the file back to its last whole line (a full disk
// may have taken half a row).
void drop_partial_last_line(const std::string& path);

// Prints the lines at or above the threshold (--log-level; default warnings
// and errors) to stderr (a LogSink).
void log_to_stderr(mh_log_level level, const std::string& source, const std::string& msg);
void set_log_threshold(mh_log_level level);
// "error", "warn", "info" or "debug" as a level; nullopt for anything else.
std::optional<mh_log_level> parse_log_level(const std::string& text);

// `code`, or 1 in its place when standard output could not be written (a
// full disk, /dev/full): flushes it and says why on stderr. Output that never
// arrived is not a success.
int with_output_written(int code);

// The command line this process was started with, shell-quoted, for the
// result sidecars (result_sidecar.hpp).
void set_command_line(int argc, const char* const* argv);
const std::string& command_line();

// A 40-column bar on stderr, drawn only when stderr is a terminal.
struct ProgressBar {
  ProgressBar();
  bool enabled;
  void operator()(double fraction) const;
};

}  // namespace mh::cli
