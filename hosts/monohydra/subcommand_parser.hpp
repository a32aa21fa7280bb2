// The subcommands' argument parsing on CLI11: each subcommand declares its
// options on a CLI::App (which gives it --help), and this parses the
// arguments and reports what is wrong in monohydra's words. Values stay
// strings here: the subcommand checks them with its own messages.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace mh::cli {

// A subcommand's parser: `name` after "monohydra", `description` for --help.
std::unique_ptr<CLI::App> subcommand_app(const std::string& name, const std::string& description);

// Parses `args` (the words after the subcommand). nullopt to go on; else the
// exit status after printing --help (0) or the error (2): an unknown option,
// a missing value.
std::optional<int> parse_subcommand(CLI::App& app, const std::vector<std::string>& args);

}  // namespace mh::cli
