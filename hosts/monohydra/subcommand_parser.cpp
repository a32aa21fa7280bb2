#include "subcommand_parser.hpp"

#include <iostream>

namespace mh::cli {

std::unique_ptr<CLI::App> subcommand_app(const std::string& name, const std::string& description) {
  auto app = std::make_unique<CLI::App>(description, "monohydra " + name);
  app->set_help_flag("-h,--help", "print this help and exit");
  app->allow_extras();  // reported below in monohydra's words
  return app;
}

std::optional<int> parse_subcommand(CLI::App& app, const std::vector<std::string>& args) {
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 pops from the back
  try {
    app.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::ParseError& err) {
    std::cerr << app.get_name() << ": " << err.what() << " (" << app.get_name()
              << " --help lists its options)\n";
    return 2;
  }
  for (const auto& extra : app.remaining()) {
    if (!extra.empty() && extra[0] == '-') {
      std::cerr << "monohydra: unknown option '" << extra << "' (" << app.get_name()
                << " --help lists its options)\n";
      return 2;
    }
  }
  return std::nullopt;
}

}  // namespace mh::cli
