// monohydra: simulate hydraulically actuated multibody systems whose
// formulations and components are plugins.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "sweep_command.hpp"

namespace {
int dispatch(const std::string& cmd, const std::vector<std::string>& args) {
  if (cmd == "plugins") return mh::cli::plugins(args);
  if (cmd == "run") return mh::cli::run(args);
  if (cmd == "compare") return mh::cli::compare(args);
  if (cmd == "validate") return mh::cli::validate(args);
  if (cmd == "sweep") return mh::cli::run_sweep(args);
  if (cmd == "--help" || cmd == "-h" || cmd == "help") return mh::cli::usage(0);
  return mh::cli::usage(2);
}
}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
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
  // Output that never arrived (stdout on a full disk, /dev/full) is not a success.
  errno = 0;
  std::cout.flush();
  if (!std::cout || std::fflush(stdout) != 0 || std::ferror(stdout) != 0) {
    std::cerr << "monohydra: cannot write to standard output: "
              << (errno != 0 ? std::strerror(errno) : "write failed") << '\n';
    if (code == 0) code = 1;
  }
  return code;
}
