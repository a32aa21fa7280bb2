// monohydra: simulate hydraulically actuated multibody systems whose
// formulations and components are plugins.
#include <string>
#include <vector>

#include "commands.hpp"

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty()) return mh::cli::run_default();
  const std::string cmd = args.front();
  args.erase(args.begin());
  if (cmd == "plugins") return mh::cli::plugins(args);
  if (cmd == "run") return mh::cli::run(args);
  if (cmd == "compare") return mh::cli::compare(args);
  if (cmd == "--help" || cmd == "-h" || cmd == "help") return mh::cli::usage(0);
  return mh::cli::usage(2);
}
