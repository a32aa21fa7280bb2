// A parameter by path (as --set names it) as the engine's sensitivities take
// it (sensitivities.hpp): how a unit change of the path's value moves the
// values the engine changes in place. Found the way --set would change it:
// the model's text with the value set a little above and below, parsed, and
// the bodies and gravity compared, so that a mass from which the file
// derives an inertia (a shape) moves both.
#pragma once

#include <string>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/sensitivities.hpp"

namespace mh::host {

// `text` is the model file's (named `label` in errors, relative paths from
// `base_dir`), `file` what it parsed to. Refused with std::invalid_argument
// starting with the path: a path the file does not write, one that is not
// a number, and one that is not a body's mass, com or inertia, gravity, or a
// component's option (whether the component changes that option in place,
// the engine asks it when tracking begins).
ParameterDirection parameter_direction(const std::string& text, const std::string& label,
                                       const std::string& base_dir, const ModelFile& file,
                                       const std::string& path);

}  // namespace mh::host
