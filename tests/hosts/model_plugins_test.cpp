// Which library a component comes from: `plugins --model` shows a model's
// plugin_paths, an id two libraries offer is listed with both and is an error
// only for a model that uses it without choosing (plugins: {ID: LIBRARY}),
// and run and compare name the library of every component they used.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "build_paths.hpp"
#include "cli_runner.hpp"

namespace {

using mh::test::CliResult;
using mh::test::run_cli;

const std::string kClashLibrary =
    std::string(mh::test::paths::clash_plugin_dir) + "/clashing_ids.so";
const std::string kShippedPenalty =
    std::string(mh::test::paths::plugin_dir) + "/monohydra-penalty.so";

// The shipped four-bar with the clashing library's folder in plugin_paths and
// `extra` top-level lines.
std::filesystem::path fourbar_with_clash(const std::string& name, const std::string& extra) {
  const auto path = mh::test::scratch_dir("model-plugins-" + name) / "fourbar.yaml";
  std::ofstream(path) << "plugin_paths: [" << mh::test::paths::clash_plugin_dir << "]\n"
                      << extra << mh::test::read_text(mh::test::shipped_model("fourbar.yaml"));
  return path;
}

// A pendulum hung on the clashing library's own spring, under open-loop.
std::filesystem::path spring_pendulum(const std::string& extra) {
  const auto path = mh::test::scratch_dir("model-plugins-spring") / "spring.yaml";
  std::ofstream(path) << "plugin_paths: [" << mh::test::paths::clash_plugin_dir << "]\n"
                      << extra
                      << "units: {length: m, mass: kg, time: s, angle: rad}\n"
                         "gravity: [0, -9.81, 0]\n"
                         "bodies:\n"
                         "  - {name: link, parent: ground, joint: {type: revolute, at: [0, 0, 0],"
                         " axis: [0, 0, 1]}, mass: 1.0, shape: {type: beam, length: 1.0}}\n"
                         "subsystems:\n"
                         "  - name: spring\n"
                         "    type: clash-spring\n"
                         "    stiffness: 40\n"
                         "    points: {a: {body: link, at: [1, 0, 0]}, b: {body: ground, at: [1, "
                         "-1, 0]}}\n"
                         "formulation: open-loop\n"
                         "solver: {dt: 0.001, t_end: 0.05}\n";
  return path;
}

TEST(ModelPlugins, PluginsWithAModelSearchesItsPluginPathsFirst) {
  const auto model = fourbar_with_clash("search", "");
  const CliResult r = run_cli("plugins --model " + model.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto search =
      r.output.find(std::string("search path: ") + mh::test::paths::clash_plugin_dir);
  EXPECT_NE(search, std::string::npos) << r.output;
  EXPECT_NE(r.output.find("subsystem    clash-spring"), std::string::npos) << r.output;
  // Without the model the folder is not searched.
  const CliResult plain = run_cli("plugins");
  EXPECT_EQ(plain.output.find("clash-spring"), std::string::npos) << plain.output;
}

TEST(ModelPlugins, AnIdOfferedTwiceIsListedWithBothLibraries) {
  const CliResult r = run_cli("plugins --model " + fourbar_with_clash("listed", "").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto line = r.output.find("offered twice: formulation 'penalty' by");
  ASSERT_NE(line, std::string::npos) << r.output;
  const std::string rest = r.output.substr(line, r.output.find('\n', line) - line);
  EXPECT_NE(rest.find("clashing_ids.so"), std::string::npos) << rest;
  EXPECT_NE(rest.find("monohydra-penalty.so"), std::string::npos) << rest;
  EXPECT_NE(rest.find("must say which: plugins: {penalty: LIBRARY.so}"), std::string::npos) << rest;
}

TEST(ModelPlugins, UsingAnIdOfferedTwiceWithoutChoosingIsAnErrorNamingBothLibraries) {
  const CliResult r = run_cli("validate " + fourbar_with_clash("ambiguous", "").string() +
                              " --formulation penalty");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("formulation 'penalty' is offered by 2 libraries"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("clashing_ids.so"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("monohydra-penalty.so"), std::string::npos) << r.output;
}

TEST(ModelPlugins, TheModelsPluginsMapChoosesTheLibraryOfAnIdOfferedTwice) {
  const auto shipped =
      fourbar_with_clash("chosen-shipped", "plugins: {penalty: " + kShippedPenalty + "}\n");
  const CliResult ok = run_cli("run " + shipped.string() + " --formulation penalty --t-end 0.01");
  ASSERT_EQ(ok.code, 0) << ok.output;
  EXPECT_NE(ok.output.find("formulation  penalty"), std::string::npos) << ok.output;
  const auto line = ok.output.find("  formulation  penalty");
  ASSERT_NE(line, std::string::npos) << ok.output;
  EXPECT_NE(ok.output.substr(line, ok.output.find('\n', line) - line).find(kShippedPenalty),
            std::string::npos)
      << ok.output;
  // Choosing the other library takes it: its penalty refuses to be created.
  const auto other =
      fourbar_with_clash("chosen-fixture", "plugins: {penalty: " + kClashLibrary + "}\n");
  const CliResult refused = run_cli("validate " + other.string() + " --formulation penalty");
  EXPECT_EQ(refused.code, 1) << refused.output;
  EXPECT_NE(refused.output.find("clashing-ids fixture's penalty is not a formulation"),
            std::string::npos)
      << refused.output;
}

TEST(ModelPlugins, AChoiceOfALibraryThatDoesNotOfferTheIdIsAnError) {
  const auto model =
      fourbar_with_clash("wrong-choice", "plugins: {double-step: " + kClashLibrary + "}\n");
  const CliResult r = run_cli("validate " + model.string());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("formulation 'double-step' is to come from"), std::string::npos)
      << r.output;
}

TEST(ModelPlugins, AChosenLibraryThatCannotBeLoadedNamesTheFieldOfTheModelFile) {
  const auto model = fourbar_with_clash("missing", "plugins: {penalty: no/such/library.so}\n");
  const CliResult r = run_cli("validate " + model.string());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("plugins.penalty"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("no/such/library.so"), std::string::npos) << r.output;
}

TEST(ModelPlugins, TheOtherComponentsOfBothLibrariesStayUsable) {
  // The clashing library's spring and the shipped open-loop, with penalty
  // offered twice and never used: no error.
  const CliResult r = run_cli("run " + spring_pendulum("").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto line = r.output.find("  subsystem    clash-spring");
  ASSERT_NE(line, std::string::npos) << r.output;
  EXPECT_NE(r.output.substr(line, r.output.find('\n', line) - line).find("clashing_ids.so"),
            std::string::npos)
      << r.output;
}

TEST(ModelPlugins, CompareNamesTheLibraryOfEveryFormulationItRan) {
  const auto model = fourbar_with_clash("compare", "plugins: {penalty: " + kShippedPenalty + "}\n");
  const CliResult r = run_cli("compare " + model.string() + " --t-end 0.01");
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* id : {"  formulation  double-step", "  formulation  penalty",
                         "  integrator   trapezoidal", "  subsystem    "}) {
    const auto line = r.output.find(id);
    ASSERT_NE(line, std::string::npos) << id << "\n" << r.output;
    EXPECT_NE(
        r.output.substr(line, r.output.find('\n', line) - line).find(mh::test::paths::plugin_dir),
        std::string::npos)
        << id << "\n"
        << r.output;
  }
}

TEST(ModelPlugins, LogLevelInfoShowsDoubleStepsPartition) {
  const std::string fourbar = mh::test::shipped_model("fourbar.yaml");
  const CliResult info = run_cli("--log-level info validate " + fourbar);
  ASSERT_EQ(info.code, 0) << info.output;
  EXPECT_NE(info.output.find("info: "), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("independent coordinates: "), std::string::npos) << info.output;
  const CliResult quiet = run_cli("validate " + fourbar);
  EXPECT_EQ(quiet.output.find("independent coordinates: "), std::string::npos) << quiet.output;
  const CliResult bad = run_cli("validate " + fourbar + " --log-level loud");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("--log-level expects error, warn, info or debug, got 'loud'"),
            std::string::npos)
      << bad.output;
}

}  // namespace
