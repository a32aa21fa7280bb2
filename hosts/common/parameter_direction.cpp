#include "parameter_direction.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "model_settings.hpp"
#include "monohydra/core/input_error.hpp"
#include "monohydra/cpp/number_text.hpp"
#include "parameter_path.hpp"

namespace mh::host {

namespace {

ModelFile parsed_with(const std::string& text, const std::string& label,
                      const std::string& base_dir, const std::string& path, double value) {
  const SetText set = apply_settings(text, label, {{path, monohydra::exact_number(value)}});
  try {
    return parse_model_text(
        set.text, label + " (with " + path + "=" + monohydra::exact_number(value) + ")", base_dir);
  } catch (const InputError& err) {
    throw std::invalid_argument(
        path + ": the model with it moved by a millionth is refused: " + err.what());
  }
}

}  // namespace

ParameterDirection parameter_direction(const std::string& text, const std::string& label,
                                       const std::string& base_dir, const ModelFile& file,
                                       const std::string& path) {
  const std::vector<std::string> parts = split_path(path);
  const bool body_value = parts.size() >= 3 && parts[0] == "bodies" &&
                          (parts[2] == "mass" || parts[2] == "com" || parts[2] == "inertia" ||
                           parts[2] == "payload" || parts[2] == "z0" || parts[2] == "zd0");
  // A load's mass moves the body's linear inertial parameters linearly
  // (its centre and size do not: they are differenced as the others).
  const bool payload =
      body_value && parts[2] == "payload" && parts.size() == 4 && parts[3] == "mass";
  const bool gravity = !parts.empty() && parts[0] == "gravity";
  // A component's option, or an entry of one that is a table
  // (subsystems/valve/flow_table/3/2): the key is the rest of the path.
  const bool option = parts.size() >= 3 && parts[0] == "subsystems";
  if (!body_value && !gravity && !option)
    throw std::invalid_argument(
        path +
        ": not a parameter sensitivities take: they take bodies' mass, com and inertia, "
        "their initial coordinates and rates, gravity, and the options a component changes in "
        "place (bodies/NAME/mass, bodies/NAME/com/I, bodies/NAME/inertia/I, "
        "bodies/NAME/payload/mass, bodies/NAME/z0, "
        "bodies/NAME/zd0, gravity/I, subsystems/NAME/KEY, subsystems/NAME/TABLE/ROW/COLUMN)");
  const YAML::Node root = YAML::Load(text);
  const std::string why = check_path(root, path);
  if (!why.empty()) throw std::invalid_argument(path + ": " + why);
  const std::optional<YAML::Node> node = value_at(root, path);
  if (!node || !node->IsScalar())
    throw std::invalid_argument(path + ": the model file writes no number there (" +
                                (node ? std::string("a list or mapping") : "nothing") +
                                "): write the value to make it a parameter");
  double value = 0.0;
  try {
    value = node->as<double>();
  } catch (const YAML::Exception&) {
    throw std::invalid_argument(path + ": expected a number, the file writes '" + node->Scalar() +
                                "'");
  }
  if (!std::isfinite(value)) throw std::invalid_argument(path + ": its value is not finite");
  if (option) {
    // Component options are SI whatever the file's units (docs/model-format.md):
    // the engine asks the instance whether it changes this one in place.
    ParameterDirection p;
    p.path = path;
    p.value = value;
    p.subsystem = parts[1];
    p.key = parts[2];
    for (size_t k = 3; k < parts.size(); ++k) p.key += "/" + parts[k];
    p.option = 1.0;
    return p;
  }
  // Central differences of the parsed model: exact for what the parser makes
  // linear in the value (a shape's inertia in its mass, a unit's factor).
  // A load's mass, exactly linear, one-sided (an empty bucket's 0 kg is a
  // bound) and by a whole kilogram or the load itself (a millionth of one
  // beside the body's tonnes would be lost to round-off).
  const double delta = (payload ? 1.0 : 1e-6) * std::max(std::abs(value), 1.0);
  const ModelFile plus = parsed_with(text, label, base_dir, path, value + delta);
  const ModelFile minus = parsed_with(text, label, base_dir, path, payload ? value : value - delta);
  ParameterDirection p;
  p.path = path;
  p.value = value;
  const double scale = 1.0 / ((payload ? 1.0 : 2.0) * delta);
  for (size_t j = 0; j < file.model.bodies.size(); ++j) {
    const Body& a = plus.model.bodies[j];
    const Body& b = minus.model.bodies[j];
    if (a.mass == b.mass && a.com_B == b.com_B && a.inertia_B == b.inertia_B) continue;
    ParameterDirection::BodyChange c;
    c.body = static_cast<int>(j);
    c.mass = (a.mass - b.mass) * scale;
    c.about_origin = payload;
    if (payload) {
      const auto origin_inertia = [](const Body& x) {
        return Eigen::Matrix3d(x.inertia_B +
                               x.mass * (x.com_B.squaredNorm() * Eigen::Matrix3d::Identity() -
                                         x.com_B * x.com_B.transpose()));
      };
      c.com = (a.mass * a.com_B - b.mass * b.com_B) * scale;
      c.inertia = (origin_inertia(a) - origin_inertia(b)) * scale;
    } else {
      c.com = (a.com_B - b.com_B) * scale;
      c.inertia = (a.inertia_B - b.inertia_B) * scale;
    }
    p.bodies.push_back(c);
  }
  for (size_t j = 0; j < file.model.bodies.size(); ++j) {
    const Body& a = plus.model.bodies[j];
    const Body& b = minus.model.bodies[j];
    if (a.z0 == b.z0 && a.zd0 == b.zd0) continue;
    ParameterDirection::InitialChange c;
    c.coordinate = static_cast<int>(j);
    c.z0 = (a.z0 - b.z0) * scale;
    c.zd0 = (a.zd0 - b.zd0) * scale;
    p.initial.push_back(c);
  }
  p.gravity = (plus.model.gravity - minus.model.gravity) * scale;
  if (p.bodies.empty() && p.initial.empty() && p.gravity.isZero(0.0))
    throw std::invalid_argument(path +
                                ": changing it changes no body, no initial state and no gravity");
  return p;
}

}  // namespace mh::host
