// The rule checker of the FMU tests can fail: each broken rule in a small,
// otherwise valid description is reported.
#include "model_description_rules.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

const char* kValid = R"(<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="3.0" modelName="m" instantiationToken="{t}">
  <CoSimulation modelIdentifier="m" fixedInternalStepSize="0.001" canGetAndSetFMUState="true"/>
  <UnitDefinitions><Unit name="m"><BaseUnit m="1"/></Unit><Unit name="s"><BaseUnit s="1"/></Unit></UnitDefinitions>
  <DefaultExperiment startTime="0" stopTime="1"/>
  <ModelVariables>
    <Float64 name="time" valueReference="0" causality="independent" variability="continuous" unit="s"/>
    <Float64 name="x" valueReference="1" causality="output" unit="m"/>
    <Float64 name="u" valueReference="2" causality="input" start="0" min="-1" max="1"/>
    <Float64 name="k" valueReference="3" causality="parameter" variability="fixed" initial="exact" start="2"/>
  </ModelVariables>
  <ModelStructure><Output valueReference="1"/><InitialUnknown valueReference="1"/></ModelStructure>
</fmiModelDescription>
)";

std::vector<std::string> violations_of(const std::string& text) {
  pugi::xml_document doc;
  EXPECT_TRUE(doc.load_string(text.c_str()));
  return mh::test::model_description_violations(doc);
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(ModelDescriptionRules, AValidDescriptionBreaksNone) {
  const auto v = violations_of(kValid);
  EXPECT_TRUE(v.empty()) << v.front();
}

TEST(ModelDescriptionRules, EachBrokenRuleIsReported) {
  const std::vector<std::pair<std::string, std::string>> breaks = {
      {"valueReference=\"2\"", "valueReference=\"1\""},        // a VR twice
      {"name=\"u\"", "name=\"x\""},                            // a name twice
      {"initial=\"exact\" start=\"2\"", "initial=\"exact\""},  // parameter without start
      {"causality=\"output\" unit=\"m\"", "causality=\"output\" unit=\"m\" start=\"1\""},
      {"causality=\"input\" start=\"0\"", "causality=\"input\""},  // input without start
      {"unit=\"m\"/>", "unit=\"Pa\"/>"},                           // undeclared unit
      {"canGetAndSetFMUState", "canGetAndSetFMUstate"},            // 2.0's spelling in 3.0
      {"<Output valueReference=\"1\"/>", ""},                      // an output not listed
      {"variability=\"fixed\"", "variability=\"continuous\""},     // a continuous parameter
      {"causality=\"independent\"", "causality=\"local\""},        // no independent variable
      {"modelIdentifier=\"m\"", "modelIdentifier=\"1m\""},
      {"start=\"0\" min", "start=\"5\" min"},                         // start out of range
      {"<DefaultExperiment", "<ModelVariables/><DefaultExperiment"},  // out of order
  };
  for (const auto& [from, to] : breaks)
    EXPECT_FALSE(violations_of(replaced(kValid, from, to)).empty()) << from << " -> " << to;
}

}  // namespace
