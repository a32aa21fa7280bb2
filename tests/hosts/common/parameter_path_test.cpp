// Model paths in normalized form: named list items, formulation and
// integrator whether written as a name or a mapping, solver settings the file
// leaves out; a path that is not there is refused with what is there.
#include "parameter_path.hpp"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

namespace mh::host {
namespace {

const char* kModel = R"(
formulation: penalty
subsystems:
  - {name: V1, type: volume, volume: 4.7e-5}
  - {name: valve, type: valve-4-3, flow_coefficient: 2.1e-8}
bodies:
  - {name: body1, mass: 225}
solver: {dt: 0.001}
)";

TEST(SweepParameterPath, FormulationNameAddressesTheScalarAndTheMappingForm) {
  YAML::Node scalar = YAML::Load(kModel);
  EXPECT_EQ(check_path(scalar, "formulation/name"), "");
  set_path(scalar, "formulation/name", YAML::Node("double-step"));
  EXPECT_EQ(scalar["formulation"]["name"].as<std::string>(), "double-step");

  YAML::Node mapping = YAML::Load("formulation: {name: penalty, alpha: 1e11}\n");
  set_path(mapping, "formulation/alpha", YAML::Node("1e9"));
  EXPECT_EQ(mapping["formulation"]["name"].as<std::string>(), "penalty");
  EXPECT_EQ(mapping["formulation"]["alpha"].as<std::string>(), "1e9");

  // Not written at all: the default component, with the option.
  YAML::Node none = YAML::Load("bodies: []\n");
  set_path(none, "integrator/rho_inf", YAML::Node("0.5"));
  EXPECT_EQ(none["integrator"]["name"].as<std::string>(), "trapezoidal");
  EXPECT_EQ(none["integrator"]["rho_inf"].as<double>(), 0.5);
}

TEST(SweepParameterPath, NamedListItemsAreAddressedByNameAndOnlyTheirValueChanges) {
  YAML::Node root = YAML::Load(kModel);
  set_path(root, "subsystems/valve/flow_coefficient", YAML::Node("4e-8"));
  EXPECT_EQ(root["subsystems"][1]["flow_coefficient"].as<double>(), 4e-8);
  EXPECT_EQ(root["subsystems"][0]["volume"].as<double>(), 4.7e-5);  // the other item untouched
  EXPECT_EQ(root["subsystems"][1]["name"].as<std::string>(), "valve");
  set_path(root, "bodies/0/mass", YAML::Node("300"));  // or by index
  EXPECT_EQ(root["bodies"][0]["mass"].as<double>(), 300);
  EXPECT_EQ(root["subsystems"].size(), 2u);
}

TEST(SweepParameterPath, SolverSettingsTheFileLeavesOutCanBeSetButUnknownOnesNot) {
  YAML::Node root = YAML::Load("bodies: []\n");
  set_path(root, "solver/t_end", YAML::Node("2"));
  EXPECT_EQ(root["solver"]["t_end"].as<double>(), 2.0);
  EXPECT_NE(check_path(root, "solver/dtt").find("no solver setting 'dtt'"), std::string::npos);
}

TEST(SweepParameterPath, AMissingSegmentIsRefusedWithWhatIsThere) {
  const YAML::Node root = YAML::Load(kModel);
  EXPECT_EQ(check_path(root, "subsystems/valve/flow_coef"),
            "no 'flow_coef' in subsystems/valve (it has name, type, flow_coefficient)");
  EXPECT_EQ(check_path(root, "subsystems/valv/flow_coefficient"),
            "no item named 'valv' in subsystems (it has V1, valve)");
  EXPECT_EQ(check_path(root, "gravity"),
            "no 'gravity' in the model (it has formulation, subsystems, bodies, solver)");
  EXPECT_NE(check_path(root, "subsystems//x").find("empty segment"), std::string::npos);
  YAML::Node copy = YAML::Clone(root);
  EXPECT_THROW(set_path(copy, "bodies/body9/mass", YAML::Node("1")), std::invalid_argument);
}

}  // namespace
}  // namespace mh::host
