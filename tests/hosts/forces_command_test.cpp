// monohydra forces: the excavator's ISO 6015 tool forces as the core computes
// them from what the model file gives (the relief valve's setting, the
// cylinders' pistons and strokes, the lip or a bucket-soil's edge), and bad
// input refused with what was expected.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "hosts/cli_runner.hpp"
#include "models/excavator_dig_model.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/tool_forces.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

using test::CliResult;
using test::run_cli;

constexpr double kPi = 3.14159265358979323846;

std::string excavator() {
  return test::source_path("models/excavator-ls.yaml");
}

// The core's force for `cylinder` about `joint`, as the command prints it.
std::string expected_line(const std::string& cylinder, int joint, const char* what) {
  const ModelFile file = load_model_file(excavator());
  for (const SubsystemSpec& s : file.subsystems) {
    if (s.name != cylinder) continue;
    ToolForceSpec spec;
    spec.coordinate = joint;
    spec.lip = BodyPoint{3, Eigen::Vector3d(1.25, 0.0, -0.58)};
    spec.cylinder_a = s.points.at("a").point;
    spec.cylinder_b = s.points.at("b").point;
    const double d = s.options.at("piston_diameter").number, l = s.options.at("length").number;
    spec.area = 0.25 * kPi * d * d;
    spec.pressure = 32e6;  // the relief valve's cracking_pressure
    spec.length_min = l;
    spec.length_max = 2.0 * l;
    const ToolForce f = tool_force(file.model, spec);
    char text[128];
    std::snprintf(text, sizeof(text), "%s '%s' about the %s's pivot: %.1f kN (", what,
                  cylinder.c_str(), file.model.bodies[static_cast<size_t>(joint)].name.c_str(),
                  f.largest.force / 1e3);
    return text;
  }
  ADD_FAILURE() << cylinder;
  return "";
}

TEST(ForcesCommand, PrintsTheBucketAndArmCylindersToolForcesAtTheReliefSetting) {
  const CliResult r = run_cli("forces " + excavator() +
                              " --bucket-cylinder bucket_cyl --arm-cylinder arm_cyl --lip "
                              "bucket:1.25,0,-0.58");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("at 32 MPa (relief-valve 'relief')"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(expected_line("bucket_cyl", 3, "bucket cylinder")), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find(expected_line("arm_cyl", 2, "arm cylinder")), std::string::npos)
      << r.output;
}

// Without --lip, the edge of the model's bucket-soil is the lip; --pressure
// replaces the relief setting, and the forces scale with it.
TEST(ForcesCommand, TheLipDefaultsToTheBucketSoilsEdgeAndThePressureScalesTheForces) {
  std::string model = test::excavator_dig_model(true);
  const auto path = test::scratch_dir("forces") / "excavator-dig.yaml";
  std::ofstream(path) << model;
  const CliResult r =
      run_cli("forces " + path.string() + " --bucket-cylinder bucket_cyl --arm-cylinder arm_cyl");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("the lip on 'bucket' at (1.25, 0, -0.58) m"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find(expected_line("bucket_cyl", 3, "bucket cylinder")), std::string::npos)
      << r.output;
  const CliResult half = run_cli("forces " + path.string() +
                                 " --bucket-cylinder bucket_cyl --arm-cylinder arm_cyl "
                                 "--pressure 16e6");
  ASSERT_EQ(half.code, 0) << half.output;
  EXPECT_NE(half.output.find("at 16 MPa (--pressure)"), std::string::npos) << half.output;
  const auto kn = [](const std::string& out) {
    const size_t at = out.find("bucket's pivot: ");
    return at == std::string::npos ? 0.0 : std::stod(out.substr(at + 16));
  };
  EXPECT_NEAR(kn(half.output), 0.5 * kn(r.output), 0.1);
  // Three bucket-soils (an odd count as well as more than one): whose edge
  // is the lip is not the command's guess.
  const size_t soil = model.find("  - {name: soil,");
  ASSERT_NE(soil, std::string::npos);
  std::string second = model.substr(soil, model.find("}}}\n", soil) + 4 - soil);
  second.replace(second.find("name: soil"), 10, "name: soil2");
  model.insert(soil, second);
  second.replace(second.find("name: soil2"), 11, "name: soil3");
  model.insert(soil, second);
  const auto two = test::scratch_dir("forces") / "three-soils.yaml";
  std::ofstream(two) << model;
  const CliResult both =
      run_cli("forces " + two.string() + " --bucket-cylinder bucket_cyl --arm-cylinder arm_cyl");
  EXPECT_EQ(both.code, 2) << both.output;
  EXPECT_NE(both.output.find("the model has no single bucket-soil whose edge it would be"),
            std::string::npos)
      << both.output;
}

TEST(ForcesCommand, BadInputIsRefusedWithWhatWasExpectedAndExitTwo) {
  const std::string base =
      "forces " + excavator() + " --bucket-cylinder bucket_cyl --arm-cylinder arm_cyl";
  const struct {
    std::string args, expected;
  } cases[] = {
      {"forces " + excavator() +
           " --bucket-cylinder bucket --arm-cylinder arm_cyl --lip "
           "bucket:1,0,0",
       "--bucket-cylinder bucket: the model has no cylinder 'bucket' (its cylinders: boom_cyl_l, "
       "boom_cyl_r, arm_cyl, bucket_cyl, slew_cyl)"},
      {"forces " + excavator() +
           " --bucket-cylinder bucket_cyl --arm-cylinder relief --lip "
           "bucket:1,0,0",
       "--arm-cylinder relief: subsystem 'relief' is a relief-valve, not a cylinder"},
      {base, "give the bucket lip as --lip BODY:X,Y,Z"},
      {base + " --lip scoop:1,0,0", "--lip expects BODY:X,Y,Z with a body of the model"},
      {base + " --lip bucket:1,0", "--lip expects BODY:X,Y,Z"},
      {base + " --lip bucket:1.25,0,-0.58 --pressure -1",
       "--pressure expects a positive pressure (Pa), got '-1'"},
      {"forces /nonexistent.yaml --bucket-cylinder a --arm-cylinder b", "/nonexistent.yaml"},
      {"forces " + excavator() + " --arm-cylinder arm_cyl", "--bucket-cylinder is required"},
  };
  for (const auto& c : cases) {
    const CliResult r = run_cli(c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_EQ(r.output.find("ISO 6015"), std::string::npos) << r.output;  // nothing half printed
  }
}

}  // namespace
}  // namespace mh
