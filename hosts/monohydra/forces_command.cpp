// monohydra forces MODEL --bucket-cylinder NAME --arm-cylinder NAME: the
// excavator's rated tool forces of ISO 6015 (tool_forces.hpp): at the bucket
// lip, the bucket cylinder's about the bucket's pivot and the arm cylinder's
// about the arm's, each the largest over the cylinder's stroke with its
// pose, and at the model's own pose (docs/soil.md).
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "commands.hpp"
#include "monohydra/core/input_error.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/tool_forces.hpp"
#include "subcommand_parser.hpp"

namespace mh::cli {

namespace {

constexpr double kPi = 3.14159265358979323846;

// A positive number option of a subsystem, or nullopt with the message.
std::optional<double> positive(const SubsystemSpec& s, const char* key, const std::string& path) {
  const auto it = s.options.find(key);
  if (it == s.options.end() || it->second.kind != OptionValue::Kind::number ||
      !(it->second.number > 0.0)) {
    std::cerr << "monohydra: forces: " << path << ": cylinder '" << s.name << "' has no positive '"
              << key << "' to take its tool force from\n";
    return std::nullopt;
  }
  return it->second.number;
}

const SubsystemSpec* find_subsystem(const ModelFile& file, const std::string& name,
                                    const char* flag) {
  for (const SubsystemSpec& s : file.subsystems)
    if (s.name == name) {
      if (s.type == "cylinder") return &s;
      std::cerr << "monohydra: forces: " << flag << " " << name << ": subsystem '" << name
                << "' is a " << s.type << ", not a cylinder\n";
      return nullptr;
    }
  std::string names;
  for (const SubsystemSpec& s : file.subsystems)
    if (s.type == "cylinder") names += (names.empty() ? "" : ", ") + s.name;
  std::cerr << "monohydra: forces: " << flag << " " << name << ": the model has no cylinder '"
            << name << "' (its cylinders: " << (names.empty() ? "none" : names) << ")\n";
  return nullptr;
}

// BODY:X,Y,Z, or the edge of the model's one bucket-soil.
std::optional<BodyPoint> lip_point(const ModelFile& file, const std::string& text) {
  if (text.empty()) {
    const SubsystemSpec* soil = nullptr;
    int soils = 0;
    for (const SubsystemSpec& s : file.subsystems)
      if (s.type == "bucket-soil") {
        soil = &s;
        ++soils;
      }
    if (soils == 1 && soil->points.count("edge") > 0) return soil->points.at("edge").point;
    std::cerr << "monohydra: forces: give the bucket lip as --lip BODY:X,Y,Z (m, in the body's "
                 "frame): the model has no single bucket-soil whose edge it would be\n";
    return std::nullopt;
  }
  const size_t colon = text.find(':');
  const std::vector<std::string> xyz =
      split_list(colon == std::string::npos ? "" : text.substr(colon + 1));
  BodyPoint p;
  p.body = -2;
  for (int b = 0; b < file.model.num_bodies(); ++b)
    if (file.model.bodies[static_cast<size_t>(b)].name == text.substr(0, colon)) p.body = b;
  if (colon == std::string::npos || xyz.size() != 3 || p.body < 0) {
    std::cerr << "monohydra: forces: --lip expects BODY:X,Y,Z with a body of the model and three "
                 "numbers (m), got '"
              << text << "'\n";
    return std::nullopt;
  }
  for (int i = 0; i < 3; ++i) {
    const std::optional<double> v = parse_number("--lip", xyz[static_cast<size_t>(i)]);
    if (!v) return std::nullopt;
    p.p_B[i] = *v;
  }
  return p;
}

// The largest relief setting of the model's relief valves, and its valve.
std::optional<double> relief_pressure(const ModelFile& file, std::string& from) {
  std::optional<double> best;
  for (const SubsystemSpec& s : file.subsystems) {
    if (s.type != "relief-valve") continue;
    const auto it = s.options.find("cracking_pressure");
    if (it == s.options.end() || it->second.kind != OptionValue::Kind::number) continue;
    if (!best || it->second.number > *best) {
      best = it->second.number;
      from = "relief-valve '" + s.name + "'";
    }
  }
  if (!best)
    std::cerr << "monohydra: forces: give the circuit's pressure as --pressure PA: the model has "
                 "no relief-valve with a cracking_pressure\n";
  return best;
}

std::string kilonewtons(double f) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f kN", f / 1e3);
  return text;
}

std::string pose(const ToolForcePoint& p, const std::string& joint) {
  char text[160];
  std::snprintf(text, sizeof(text), "%s at %.2f deg, cylinder %.3f m, lip radius %.3f m",
                joint.c_str(), p.angle * 180.0 / kPi, p.length, p.radius);
  return text;
}

}  // namespace

int forces(const std::vector<std::string>& args) {
  const auto app_holder = subcommand_app(
      "forces",
      "Print the excavator's rated tool forces of ISO 6015: at the bucket lip, tangent to its arc "
      "about the bucket's pivot with the bucket cylinder pushing, and about the arm's pivot with "
      "the arm cylinder pushing, at the relief pressure on the cap side; each the largest over "
      "the cylinder's stroke and at the model's pose.");
  CLI::App& app = *app_holder;
  std::vector<std::string> models;
  std::string bucket_name, arm_name, lip_text, pressure_text;
  app.add_option("MODEL.yaml", models, "the model file");
  app.add_option("--bucket-cylinder", bucket_name, "the cylinder that turns the bucket")
      ->required();
  app.add_option("--arm-cylinder", arm_name, "the cylinder that turns the arm")->required();
  app.add_option("--lip", lip_text,
                 "BODY:X,Y,Z, the lip's middle in the bucket's frame (m; default: the edge of "
                 "the model's bucket-soil)");
  app.add_option("--pressure", pressure_text,
                 "the circuit's pressure (Pa; default: the largest relief-valve setting)");
  if (const auto code = parse_subcommand(app, args)) return *code;
  if (models.size() != 1) {
    std::cerr << "monohydra: forces needs one model file\n";
    return 2;
  }
  ModelFile file;
  try {
    file = load_model_file(models.front());
  } catch (const InputError& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return 2;
  }
  const SubsystemSpec* bucket = find_subsystem(file, bucket_name, "--bucket-cylinder");
  const SubsystemSpec* arm = find_subsystem(file, arm_name, "--arm-cylinder");
  const std::optional<BodyPoint> lip = lip_point(file, lip_text);
  if (bucket == nullptr || arm == nullptr || !lip) return 2;
  if (lip->body < 0 || file.model.bodies[static_cast<size_t>(lip->body)].parent < 0) {
    std::cerr << "monohydra: forces: the lip must be on a bucket whose parent is the arm, not on "
                 "the ground or a body of it\n";
    return 2;
  }
  std::string from = "--pressure";
  std::optional<double> pressure;
  if (pressure_text.empty()) {
    pressure = relief_pressure(file, from);
  } else {
    pressure = parse_number("--pressure", pressure_text);
    if (pressure && !(*pressure > 0.0)) {
      std::cerr << "monohydra: forces: --pressure expects a positive pressure (Pa), got '"
                << pressure_text << "'\n";
      pressure.reset();
    }
  }
  if (!pressure) return 2;

  const int bucket_joint = lip->body;
  const int arm_joint = file.model.bodies[static_cast<size_t>(bucket_joint)].parent;
  const struct {
    const SubsystemSpec* cylinder;
    int joint;
    const char* what;
  } rows[2] = {{bucket, bucket_joint, "bucket cylinder"}, {arm, arm_joint, "arm cylinder"}};
  char head[256];
  std::snprintf(head, sizeof(head), "at %.4g MPa (%s), the lip on '%s' at (%g, %g, %g) m\n",
                *pressure / 1e6, from.c_str(),
                file.model.bodies[static_cast<size_t>(lip->body)].name.c_str(), lip->p_B[0],
                lip->p_B[1], lip->p_B[2]);
  // Both forces first: a refusal leaves nothing printed.
  std::string lines = "ISO 6015 rated tool forces of " + models.front() + "\n  " + head;
  for (const auto& row : rows) {
    const std::optional<double> d = positive(*row.cylinder, "piston_diameter", models.front());
    const std::optional<double> l = positive(*row.cylinder, "length", models.front());
    if (!d || !l) return 2;
    ToolForceSpec spec;
    spec.coordinate = row.joint;
    spec.lip = *lip;
    spec.cylinder_a =
        row.cylinder->points.count("a") ? row.cylinder->points.at("a").point : BodyPoint{};
    spec.cylinder_b =
        row.cylinder->points.count("b") ? row.cylinder->points.at("b").point : BodyPoint{};
    spec.area = 0.25 * kPi * *d * *d;
    spec.pressure = *pressure;
    // The cylinder's stroke: its chambers' lengths l2 = s - l and l3 = 2 l -
    // s stay non-negative (docs/hydraulics.md), l <= s <= 2 l.
    spec.length_min = *l;
    spec.length_max = 2.0 * *l;
    const std::string& joint = file.model.bodies[static_cast<size_t>(row.joint)].name;
    try {
      const ToolForce f = tool_force(file.model, spec);
      lines += "  " + std::string(row.what) + " '" + row.cylinder->name + "' about the " + joint +
               "'s pivot: " + kilonewtons(f.largest.force) + " (" + pose(f.largest, joint) +
               "); at the model's pose " + kilonewtons(f.initial.force) + " (" +
               pose(f.initial, joint) + ")\n";
    } catch (const std::invalid_argument& err) {
      std::cerr << "monohydra: forces: " << row.what << " '" << row.cylinder->name
                << "': " << err.what() << '\n';
      return 2;
    }
  }
  std::cout << lines;
  return 0;
}

}  // namespace mh::cli
