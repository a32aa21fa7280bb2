// units: SI only, with angles in rad or deg; sets the scale that converts the
// file's angles to radians.
#include "parser.hpp"

namespace mh::model_file_detail {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

void Parser::parse_units(const MapView& top) {
  const std::string hint =
      "write units: {length: m, mass: kg, time: s, angle: rad} (or angle: deg)";
  const YAML::Node node = top.require("units", hint);
  const MapView units(*this, node, "units", {"length", "mass", "time", "angle"});
  const auto require_unit = [&](const std::string& key, const std::string& si) {
    const YAML::Node value = units.require(key, hint);
    const std::string text = string(value, units.field(key));
    if (text != si) {
      fail(value, units.field(key),
           "expected '" + si + "' (only SI units are supported; only angles may be 'deg'), got '" +
               text + "'");
    }
  };
  require_unit("length", "m");
  require_unit("mass", "kg");
  require_unit("time", "s");
  const YAML::Node angle = units.require("angle", hint);
  const std::string angle_unit = string(angle, "units.angle");
  if (angle_unit == "rad") {
    angle_scale_ = 1.0;
  } else if (angle_unit == "deg") {
    angle_scale_ = kPi / 180.0;
  } else {
    fail(angle, "units.angle", "expected 'rad' or 'deg', got '" + angle_unit + "'");
  }
}

}  // namespace mh::model_file_detail
