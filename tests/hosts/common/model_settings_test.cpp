// Values set by path in a model file's own text (run --set): only the value's
// characters change, so every line keeps its number; what the file does not
// write is added to the tree; a value of the wrong kind is refused naming
// the setting.
#include "model_settings.hpp"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "build_paths.hpp"
#include "monohydra/core/input_error.hpp"

namespace mh::host {
namespace {

const std::string kModel =
    "# a comment that stays\n"
    "bodies:\n"
    "  - name: body1\n"
    "    mass: 225        # kg\n"
    "  - {name: body2, mass: 35, length: 1.5}\n"
    "subsystems:\n"
    "  - {name: valve, type: valve-4-3, flow_coefficient: \"2.1e-8\"}\n"
    "gravity: [0, -9.81, 0]\n"
    "formulation: penalty\n";

std::string fourbar() {
  return std::string(mh::test::paths::source_dir) + "/models/fourbar.yaml";
}

std::string replaced(const std::string& text, const std::string& from, const std::string& to) {
  std::string out = text;
  const std::size_t at = out.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  out.replace(at, from.size(), to);
  return out;
}

TEST(ModelSettings, AValueTheFileWritesChangesInPlaceAndNothingElseDoes) {
  const SetText block = apply_settings(kModel, "m.yaml", {{"bodies/body1/mass", "250"}});
  EXPECT_FALSE(block.rewritten);
  EXPECT_EQ(block.text, replaced(kModel, "mass: 225", "mass: 250"));

  // In a flow mapping, a quoted scalar and a flow sequence alike.
  const SetText flow = apply_settings(kModel, "m.yaml",
                                      {{"bodies/body2/mass", "40.5"},
                                       {"subsystems/valve/flow_coefficient", "3e-8"},
                                       {"gravity/1", "-9.80665"}});
  EXPECT_FALSE(flow.rewritten);
  std::string expected = replaced(kModel, "mass: 35", "mass: 40.5");
  expected = replaced(expected, "\"2.1e-8\"", "3e-8");
  expected = replaced(expected, "-9.81", "-9.80665");
  EXPECT_EQ(flow.text, expected);
}

TEST(ModelSettings, LaterSettingsOfOnePathWinAndListItemsAreFoundByIndexToo) {
  const SetText set =
      apply_settings(kModel, "m.yaml", {{"bodies/0/mass", "1"}, {"bodies/body1/mass", "2"}});
  EXPECT_EQ(YAML::Load(set.text)["bodies"][0]["mass"].as<double>(), 2.0);
}

TEST(ModelSettings, APathTheFileDoesNotWriteIsAddedToTheRewrittenTree) {
  const SetText set =
      apply_settings(kModel, "m.yaml", {{"bodies/body1/mass", "250"}, {"solver/dt", "0.002"}});
  EXPECT_TRUE(set.rewritten);
  const YAML::Node root = YAML::Load(set.text);
  EXPECT_EQ(root["solver"]["dt"].as<double>(), 0.002);
  EXPECT_EQ(root["bodies"][0]["mass"].as<double>(), 250.0);
  EXPECT_EQ(root["formulation"].as<std::string>(), "penalty");  // the rest as it was
}

TEST(ModelSettings, ANonNumberWhereTheFileWritesANumberIsRefusedNamingBoth) {
  try {
    apply_settings(kModel, "m.yaml", {{"bodies/body1/mass", "heavy"}});
    FAIL() << "a name accepted as a mass";
  } catch (const std::invalid_argument& err) {
    EXPECT_STREQ(err.what(),
                 "bodies/body1/mass=heavy: expected a number (the model writes 225 there), got "
                 "'heavy'");
  }
}

TEST(ModelSettings, AListAMappingAMissingPathAndAnEmptyValueAreRefused) {
  const auto refusal = [](const std::string& path, const std::string& value) {
    try {
      apply_settings(kModel, "m.yaml", {{path, value}});
    } catch (const std::invalid_argument& err) {
      return std::string(err.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(refusal("bodies", "3"), "bodies=3: the model writes a list at bodies, not one value");
  EXPECT_EQ(refusal("bodies/body1", "3"),
            "bodies/body1=3: the model writes a mapping at bodies/body1, not one value");
  EXPECT_EQ(refusal("bodies/body9/mass", "3"),
            "bodies/body9/mass=3: no item named 'body9' in bodies (it has body1, body2)");
  EXPECT_EQ(refusal("bodies/body1/mass", ""),
            "bodies/body1/mass=: expected one value, a number or a name");
  EXPECT_EQ(refusal("bodies/body1/mass", "[1, 2]"),
            "bodies/body1/mass=[1, 2]: expected one value, a number or a name");
}

TEST(ModelSettings, TextThatCouldChangeTheFilesStructureIsWrittenQuoted) {
  const SetText set =
      apply_settings(kModel, "m.yaml", {{"subsystems/valve/type", "a, b}  # the value is YAML"}});
  EXPECT_FALSE(set.rewritten);
  const YAML::Node root = YAML::Load(set.text);
  EXPECT_EQ(root["subsystems"][0]["type"].as<std::string>(), "a, b}");
  EXPECT_EQ(root["subsystems"][0]["flow_coefficient"].as<std::string>(), "2.1e-8");
}

TEST(ModelSettings, PathEqualsValueIsParsedAtTheFirstEqualsSign) {
  const PathSetting s = parse_setting("formulation/name=a=b");
  EXPECT_EQ(s.path, "formulation/name");
  EXPECT_EQ(s.value, "a=b");
  EXPECT_THROW(parse_setting("bodies/body1/mass"), std::invalid_argument);
  EXPECT_THROW(parse_setting("=3"), std::invalid_argument);
}

TEST(ModelSettings, TheParsersRefusalOfASetValueNamesTheFilesOwnLineAndTheSetting) {
  const std::string path = fourbar();
  std::ifstream in(path);
  std::string line;
  int mass_line = 0;
  for (int i = 1; std::getline(in, line); ++i)
    if (line.find("mass: 225") != std::string::npos) mass_line = i;
  ASSERT_GT(mass_line, 0);
  try {
    load_model_file(path, {{"bodies/body1/mass", "-3"}});
    FAIL() << "a negative mass accepted";
  } catch (const InputError& err) {
    EXPECT_EQ(err.mark().line, mass_line);
    const std::string what = err.what();
    EXPECT_NE(what.find(path + ":" + std::to_string(mass_line) + ":"), std::string::npos) << what;
    EXPECT_NE(what.find("(with --set bodies/body1/mass=-3)"), std::string::npos) << what;
  }
  // A refused setting names the file.
  try {
    load_model_file(path, {{"bodies/body9/mass", "3"}});
    FAIL() << "a missing body accepted";
  } catch (const InputError& err) {
    EXPECT_EQ(std::string(err.what()).rfind(path + ": --set bodies/body9/mass=3: no item", 0), 0u)
        << err.what();
  }
}

TEST(ModelSettings, ASetValueIsTheModelAsIfTheFileWroteIt) {
  const std::string path = fourbar();
  const ModelFile set = load_model_file(path, {{"bodies/body3/mass", "57.5"}});
  const ModelFile plain = load_model_file(path, {});
  ASSERT_EQ(set.model.bodies.size(), plain.model.bodies.size());
  EXPECT_EQ(set.model.bodies[2].mass, 57.5);
  EXPECT_EQ(plain.model.bodies[2].mass, 50.0);
  EXPECT_EQ(set.model.bodies[1].mass, plain.model.bodies[1].mass);
}

}  // namespace
}  // namespace mh::host
