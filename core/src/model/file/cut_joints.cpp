// cut_joints (the joints that close kinematic loops) and assembly (the bodies
// held fixed while the loops are closed).
#include <cmath>
#include <map>

#include "parser.hpp"

namespace mh::model_file_detail {

void Parser::parse_assembly(const YAML::Node& node, ModelFile& file) const {
  const MapView map(*this, node, "assembly", {"fixed"});
  if (auto fixed = map.get("fixed")) {
    file.assembly_mark = mark(*fixed);
    if (!fixed->IsSequence())
      fail(*fixed, "assembly.fixed", "expected a list of body names, got " + describe(*fixed));
    for (std::size_t i = 0; i < fixed->size(); ++i) {
      const std::string body = name((*fixed)[i], index_field("assembly.fixed", i));
      int found = -1;
      for (std::size_t j = 0; j < file.model.bodies.size(); ++j)
        if (file.model.bodies[j].name == body) found = static_cast<int>(j);
      if (found < 0)
        fail((*fixed)[i], index_field("assembly.fixed", i), "unknown body '" + body + "'");
      file.model.assembly_fixed.push_back(found);
    }
  }
}

std::vector<CutJoint> Parser::cut_joints(const YAML::Node& node) const {
  if (!node.IsSequence()) {
    fail(node, "cut_joints", "expected a list of cut joints, got " + describe(node));
  }
  std::vector<CutJoint> joints;
  std::map<std::string, SourceMark> names;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string field = index_field("cut_joints", i);
    const MapView map(*this, node[i], field, {"name", "type", "a", "b", "axis", "axis_b"});
    CutJoint joint;
    const YAML::Node name_node = map.require("name");
    joint.name = name(name_node, map.field("name"));
    check_unique(names, joint.name, name_node, map.field("name"), "cut joint");

    const YAML::Node type_node = map.require("type", "revolute, spherical or translational");
    const std::string type = string(type_node, map.field("type"));
    if (type == "revolute") {
      joint.type = CutJointType::revolute;
    } else if (type == "spherical") {
      joint.type = CutJointType::spherical;
    } else if (type == "translational") {
      joint.type = CutJointType::translational;
    } else {
      fail(type_node, map.field("type"),
           "unknown cut joint type '" + type +
               "' (expected one of: revolute, spherical, translational)");
    }
    joint.a = point(map.require("a"), map.field("a")).point;
    joint.b = point(map.require("b"), map.field("b")).point;
    if (joint.a.body == joint.b.body) {
      fail(
          map.require("b"), map.field("b.body"),
          "a cut joint must connect two different bodies (a and b are both on '" +
              (joint.a.body == kGround ? std::string(kGroundName)
                                       : body_topo_names_[static_cast<std::size_t>(joint.a.body)]) +
              "')");
    }
    if (auto axis_node = map.get("axis")) joint.axis_a = axis(*axis_node, map.field("axis"));
    joint.axis_b = joint.axis_a;
    if (auto axis_node = map.get("axis_b")) joint.axis_b = axis(*axis_node, map.field("axis_b"));
    if (planar_ && joint.type == CutJointType::translational &&
        (std::abs(joint.axis_a.z()) > 1e-9 || std::abs(joint.axis_b.z()) > 1e-9))
      fail(map.require("axis"), map.field("axis"),
           "expected an in-plane sliding axis (z = 0) in a planar model");
    joints.push_back(joint);
  }
  return joints;
}

}  // namespace mh::model_file_detail
