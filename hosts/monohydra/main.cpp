// monohydra: simulate hydraulically actuated multibody systems whose
// formulations and components are plugins.
#include <cerrno>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "call_watchdog.hpp"
#include "cli_support.hpp"
#include "commands.hpp"
#include "crash_report.hpp"
#include "plugin_check.hpp"
#include "supervised.hpp"
#include "sweep_command.hpp"

namespace {
int dispatch(const std::string& cmd, const std::vector<std::string>& args) {
  if (cmd == "plugins") return mh::cli::plugins(args);
  if (cmd == "run") return mh::cli::run(args);
  if (cmd == "compare") return mh::cli::compare(args);
  if (cmd == "check") return mh::cli::check(args);
  if (cmd == "validate") return mh::cli::supervised([&] { return mh::cli::validate(args); });
  if (cmd == "sweep") return mh::cli::run_sweep(args);
  if (cmd == "linearize") return mh::cli::supervised([&] { return mh::cli::linearize(args); });
  if (cmd == "sensitivities")
    return mh::cli::supervised([&] { return mh::cli::sensitivities(args); });
  if (cmd == "fit") return mh::cli::supervised([&] { return mh::cli::fit(args); });
  if (cmd == "estimate") return mh::cli::supervised([&] { return mh::cli::estimate(args); });
  if (cmd == "fmu") return mh::cli::supervised([&] { return mh::cli::fmu(args); });
  if (cmd == "forces") return mh::cli::supervised([&] { return mh::cli::forces(args); });
  if (cmd == "--help" || cmd == "-h" || cmd == "help") return mh::cli::usage(0);
  // Named, with the commands there are, rather than the whole usage text
  // (which hid a mistyped command's name among 50 lines).
  std::cerr << "monohydra: unknown command '" << cmd
            << "' (expected one of: plugins, run, compare, validate, sweep, check, linearize, "
               "sensitivities, fit, estimate, fmu, forces; "
               "monohydra --help shows their options)\n";
  return 2;
}

// --log-level LEVEL (or --log-level=LEVEL) anywhere on the line applies to
// every command: it is taken out before the command reads its arguments.
bool take_log_level(std::vector<std::string>& args) {
  for (size_t i = 0; i < args.size(); ++i) {
    std::string value;
    size_t taken = 0;
    if (args[i] == "--log-level") {
      if (i + 1 >= args.size()) {
        std::cerr << "monohydra: --log-level expects error, warn, info or debug\n";
        return false;
      }
      value = args[i + 1];
      taken = 2;
    } else if (args[i].rfind("--log-level=", 0) == 0) {
      value = args[i].substr(12);
      taken = 1;
    } else {
      continue;
    }
    const auto level = mh::cli::parse_log_level(value);
    if (!level) {
      std::cerr << "monohydra: --log-level expects error, warn, info or debug, got '" << value
                << "'\n";
      return false;
    }
    mh::cli::set_log_threshold(*level);
    args.erase(args.begin() + static_cast<std::ptrdiff_t>(i),
               args.begin() + static_cast<std::ptrdiff_t>(i + taken));
    --i;
  }
  return true;
}
}  // namespace

int main(int argc, char** argv) {
  mh::cli::set_command_line(argc, argv);
  // A plugin that crashes in a call this process makes (compare sets runs up
  // here; run, and the commands dispatch() supervises, do it in a child) is named.
  mh::cli::install_crash_handler(nullptr);
  // Nor can a plugin call that never returns hang it (run sets its own limit).
  mh::cli::start_call_watchdog();
  std::vector<std::string> args(argv + 1, argv + argc);
  if (!take_log_level(args)) return 2;
  int code = 2;
  try {
    if (args.empty()) {
      code = mh::cli::run_default();
    } else {
      const std::string cmd = args.front();
      args.erase(args.begin());
      code = dispatch(cmd, args);
    }
  } catch (const std::exception& err) {  // a bug: say so rather than abort
    std::cerr << "monohydra: internal error: " << err.what() << '\n';
    code = 70;
  }
  return mh::cli::with_output_written(code);
}
