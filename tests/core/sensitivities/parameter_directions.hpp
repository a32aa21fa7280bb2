// Parameters by path as the tests build them (sensitivities.hpp): what a
// unit change of a body's mass or a component's option moves, as the
// command line's --set would move it. Shared by the sensitivities' and the
// estimation's tests.
#pragma once

#include <string>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/sensitivities.hpp"

namespace mh::test {

// Body `body`'s mass, whose inertia the file derives from it (a shape).
inline ParameterDirection mass_direction(const Model& model, size_t body) {
  const Body& b = model.bodies[body];
  ParameterDirection p;
  p.path = "bodies/" + b.name + "/mass";
  p.value = b.mass;
  p.bodies.push_back({static_cast<int>(body), 1.0, Eigen::Vector3d::Zero(), b.inertia_B / b.mass});
  return p;
}

// A component's option (parameters.h), changed in place by its instance,
// at its value in the file.
inline ParameterDirection option_direction(const ModelFile& file, const std::string& subsystem,
                                           const std::string& key) {
  ParameterDirection p;
  p.path = "subsystems/" + subsystem + "/" + key;
  p.subsystem = subsystem;
  p.key = key;
  p.option = 1.0;
  for (const SubsystemSpec& s : file.subsystems)
    if (s.name == subsystem) p.value = s.options.at(key).number;
  return p;
}

}  // namespace mh::test
