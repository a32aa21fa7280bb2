// The scripts the report's 3D view needs, built into the program so that a
// report holds them and works offline: three.js and its OrbitControls
// (Debian's libjs-three, MIT licence) and the viewer (machine_view.js).
#pragma once

#include <string_view>

namespace mh::cli {

std::string_view three_js_source();        // "" when built without libjs-three
std::string_view orbit_controls_source();  // "" when built without libjs-three
std::string_view machine_view_source();

}  // namespace mh::cli
