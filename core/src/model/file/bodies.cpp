// bodies: each body with its joint, orientation, mass and shape (beam,
// cuboid, box or cylinder give com and inertia), sorted so that parents
// precede their children; the planar check; and points {body, at} on the
// sorted bodies.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <queue>
#include <string>
#include <vector>

#include "parser.hpp"

namespace mh {
const char* to_string(BodyShape::Kind kind) {
  switch (kind) {
    case BodyShape::Kind::beam:
      return "beam";
    case BodyShape::Kind::cuboid:
      return "cuboid";
    case BodyShape::Kind::box:
      return "box";
    case BodyShape::Kind::cylinder:
      return "cylinder";
    case BodyShape::Kind::none:
      break;
  }
  return "none";
}
}  // namespace mh

namespace mh::model_file_detail {

// {body: NAME, at: [x, y, z]}; the body index is into Model::bodies.
PointSpec Parser::point(const YAML::Node& node, const std::string& field) const {
  const MapView map(*this, node, field, {"body", "at"});
  PointSpec spec;
  spec.mark = mark(node);
  const YAML::Node body_node = map.require("body");
  spec.point.body = body_index(body_node, map.field("body"));
  if (auto at = map.get("at")) spec.point.p_B = length3(*at, map.field("at"));
  return spec;
}

int Parser::body_index(const YAML::Node& node, const std::string& field) const {
  const std::string body = name(node, field);
  if (body == kGroundName) return kGround;
  const auto it = body_topo_index_.find(body);
  if (it == body_topo_index_.end()) fail(node, field, unknown_body_message(body));
  return it->second;
}

std::string Parser::unknown_body_message(const std::string& body) const {
  std::vector<std::string> known = {kGroundName};
  known.insert(known.end(), body_file_names_.begin(), body_file_names_.end());
  return "unknown body '" + body + "' (expected one of: " + join(known) + ")";
}

// Bodies in file order, then resolved parents, then a stable topological
// sort (the lowest file position among the bodies whose parent is placed
// goes next, so a file already in tree order keeps its order).
void Parser::parse_bodies(const YAML::Node& node, ModelFile& file) {
  if (!node.IsSequence()) fail(node, "bodies", "expected a list of bodies, got " + describe(node));
  std::vector<RawBody> raw;
  std::map<std::string, int> file_index;
  for (std::size_t i = 0; i < node.size(); ++i) {
    raw.push_back(body(node[i], index_field("bodies", i), i));
    const std::string& body_name = raw.back().body.name;
    if (!file_index.emplace(body_name, static_cast<int>(i)).second) {
      fail(raw.back().name_node, child_field(raw.back().field, "name"),
           "duplicate body name '" + body_name + "' (first defined at " +
               location(raw[static_cast<std::size_t>(file_index[body_name])].mark) + ")");
    }
    body_file_names_.push_back(body_name);
  }

  const int n = static_cast<int>(raw.size());
  std::vector<int> parent(static_cast<std::size_t>(n), kGround);
  std::vector<std::vector<int>> children(static_cast<std::size_t>(n));
  std::priority_queue<int, std::vector<int>, std::greater<int>> ready;
  for (int i = 0; i < n; ++i) {
    const RawBody& b = raw[static_cast<std::size_t>(i)];
    if (b.parent_name == kGroundName) {
      ready.push(i);
      continue;
    }
    const auto it = file_index.find(b.parent_name);
    if (it == file_index.end()) {
      fail(b.parent_node, child_field(b.field, "parent"),
           "unknown parent body '" + b.parent_name + "' (expected one of: " + join([&] {
             std::vector<std::string> known = {kGroundName};
             for (const auto& other : raw) {
               if (other.body.name != b.body.name) known.push_back(other.body.name);
             }
             return known;
           }()) +
               ")");
    }
    parent[static_cast<std::size_t>(i)] = it->second;
    children[static_cast<std::size_t>(it->second)].push_back(i);
  }

  std::vector<int> topo_of(static_cast<std::size_t>(n), -1);
  std::vector<int> order;
  while (!ready.empty()) {
    const int i = ready.top();
    ready.pop();
    topo_of[static_cast<std::size_t>(i)] = static_cast<int>(order.size());
    order.push_back(i);
    for (const int child : children[static_cast<std::size_t>(i)]) ready.push(child);
  }
  if (static_cast<int>(order.size()) < n) report_cycle(raw, parent, topo_of);

  for (const int i : order) {
    RawBody& b = raw[static_cast<std::size_t>(i)];
    const int p = parent[static_cast<std::size_t>(i)];
    b.body.parent = p == kGround ? kGround : topo_of[static_cast<std::size_t>(p)];
    file.model.bodies.push_back(b.body);
    file.body_marks.push_back(b.mark);
    file.body_shapes.push_back(b.shape);
    body_topo_index_[b.body.name] = topo_of[static_cast<std::size_t>(i)];
    body_topo_names_.push_back(b.body.name);
  }
}

// Every unplaced body's parent is unplaced too, so following parents from
// one of them must come back round; name the bodies on that loop.
void Parser::report_cycle(const std::vector<RawBody>& raw, const std::vector<int>& parent,
                          const std::vector<int>& topo_of) const {
  int start = 0;
  while (topo_of[static_cast<std::size_t>(start)] != -1) ++start;
  std::map<int, int> step_of;
  std::vector<int> path;
  int current = start;
  while (step_of.find(current) == step_of.end()) {
    step_of[current] = static_cast<int>(path.size());
    path.push_back(current);
    current = parent[static_cast<std::size_t>(current)];
  }
  std::vector<int> cycle(path.begin() + step_of[current], path.end());
  std::rotate(cycle.begin(), std::min_element(cycle.begin(), cycle.end()), cycle.end());
  std::string text;
  for (const int i : cycle) text += raw[static_cast<std::size_t>(i)].body.name + " -> ";
  text += raw[static_cast<std::size_t>(cycle.front())].body.name;
  const RawBody& first = raw[static_cast<std::size_t>(cycle.front())];
  fail(first.parent_node, child_field(first.field, "parent"),
       "the parents form a cycle: " + text + " (every chain of parents must end at 'ground')");
}

namespace {

// A uniform box of mass m and sides d about its centre (a shape's, a
// payload's).
Eigen::Matrix3d box_inertia(double m, const Eigen::Vector3d& d) {
  const Eigen::Vector3d d2 = d.cwiseProduct(d);
  return (m / 12.0 * Eigen::Vector3d(d2.y() + d2.z(), d2.x() + d2.z(), d2.x() + d2.y()))
      .asDiagonal();
}

}  // namespace

RawBody Parser::body(const YAML::Node& node, const std::string& field, std::size_t index) const {
  const MapView map(*this, node, field,
                    {"name", "parent", "joint", "orientation", "mass", "shape", "com", "inertia",
                     "payload", "z0", "zd0"});
  RawBody raw;
  raw.field = field;
  raw.mark = mark(node);
  Body& b = raw.body;
  b.coordinate = "z" + std::to_string(index + 1);

  raw.name_node = map.require("name");
  b.name = name(raw.name_node, map.field("name"));
  if (b.name == kGroundName) {
    fail(raw.name_node, map.field("name"),
         "'ground' is reserved for the fixed world; pick another name");
  }
  raw.parent_node = map.require("parent", "'ground' or another body's name");
  raw.parent_name = name(raw.parent_node, map.field("parent"));

  const MapView joint(*this, map.require("joint"), map.field("joint"), {"type", "at", "axis"});
  const YAML::Node type_node = joint.require("type", "revolute or prismatic");
  const std::string type = string(type_node, joint.field("type"));
  if (type == "revolute") {
    b.joint = JointType::revolute;
  } else if (type == "prismatic") {
    b.joint = JointType::prismatic;
  } else {
    fail(type_node, joint.field("type"),
         "unknown joint type '" + type + "' (expected one of: revolute, prismatic)");
  }
  if (auto at = joint.get("at")) b.joint_P = length3(*at, joint.field("at"));
  if (auto axis_node = joint.get("axis")) b.axis_P = axis(*axis_node, joint.field("axis"));

  if (auto orientation_node = map.get("orientation")) {
    const MapView orientation(*this, *orientation_node, map.field("orientation"),
                              {"axis", "angle"});
    const Eigen::Vector3d u = axis(orientation.require("axis"), orientation.field("axis"));
    const double angle =
        number(orientation.require("angle"), orientation.field("angle")) * angle_scale_;
    b.R_P_B0 = Eigen::AngleAxisd(angle, u).toRotationMatrix();
  }

  const YAML::Node mass_node = map.require("mass");
  b.mass =
      bounded(positive(mass_node, map.field("mass")), mass_node, map.field("mass"), kMaxMass, "kg");

  std::optional<Eigen::Vector3d> shape_com;
  std::optional<Eigen::Matrix3d> shape_inertia;
  if (auto shape_node = map.get("shape")) {
    // The keys of its type only, so that a stray or misspelt one is named
    // with the keys that type takes (an unknown type: any, and the type's
    // error comes first).
    const YAML::Node peek = shape_node->IsMap() ? (*shape_node)["type"] : YAML::Node();
    const std::string peeked = peek && peek.IsScalar() ? peek.Scalar() : "";
    const std::vector<std::string> keys =
        peeked == "beam" || peeked == "cuboid" ? std::vector<std::string>{"type", "length"}
        : peeked == "box"                      ? std::vector<std::string>{"type", "size", "at"}
        : peeked == "cylinder" ? std::vector<std::string>{"type", "length", "radius"}
                               : std::vector<std::string>{"type", "length", "size", "radius", "at"};
    const MapView shape(*this, *shape_node, map.field("shape"), keys);
    const char* const kinds = "beam, cuboid, box or cylinder";
    const YAML::Node shape_type = shape.require("type", kinds);
    const std::string kind = string(shape_type, shape.field("type"));
    auto length_of = [&](const char* key) {
      const YAML::Node value = shape.require(key);
      return bounded(positive(value, shape.field(key)), value, shape.field(key), kMaxLength, "m");
    };
    const double m = b.mass;
    // Inertias about the centre of mass, in the body frame (uniform solids).
    if (kind == "beam" || kind == "cuboid") {
      const double length = length_of("length");
      const double ml2 = m * length * length;
      if (kind == "beam") {
        raw.shape.kind = BodyShape::Kind::beam;
        raw.shape.size = Eigen::Vector3d(length, 0.0, 0.0);
        shape_com = Eigen::Vector3d(0.5 * length, 0.0, 0.0);
        shape_inertia = Eigen::Vector3d(0.0, ml2 / 12.0, ml2 / 12.0).asDiagonal();
      } else {
        raw.shape.kind = BodyShape::Kind::cuboid;
        raw.shape.size = Eigen::Vector3d::Constant(length);
        shape_com = Eigen::Vector3d::Zero();
        shape_inertia = Eigen::Matrix3d::Identity() * (ml2 / 6.0);
      }
    } else if (kind == "box") {
      const YAML::Node size_node = shape.require("size", "[x, y, z] in m, each positive");
      const Eigen::Vector3d d = length3(size_node, shape.field("size"));
      if (!(d.minCoeff() > 0.0))
        fail(size_node, shape.field("size"), "expected three positive sides [x, y, z] (m)");
      raw.shape.kind = BodyShape::Kind::box;
      raw.shape.size = d;
      if (auto at = shape.get("at")) raw.shape.at = length3(*at, shape.field("at"));
      shape_com = raw.shape.at;
      shape_inertia = box_inertia(m, d);
    } else if (kind == "cylinder") {
      const double length = length_of("length");
      const double r = length_of("radius");
      raw.shape.kind = BodyShape::Kind::cylinder;
      raw.shape.size = Eigen::Vector3d(length, r, r);
      shape_com = Eigen::Vector3d(0.5 * length, 0.0, 0.0);
      const double across = m * (3.0 * r * r + length * length) / 12.0;
      shape_inertia = Eigen::Vector3d(0.5 * m * r * r, across, across).asDiagonal();
    } else {
      fail(shape_type, shape.field("type"),
           "unknown shape type '" + kind + "' (expected one of: " + kinds + ")");
    }
  }
  const std::string without_shape = "required when no shape is given";
  if (auto com = map.get("com")) {
    b.com_B = length3(*com, map.field("com"));
  } else if (shape_com) {
    b.com_B = *shape_com;
  } else {
    map.require("com", without_shape);
  }
  if (auto inertia_node = map.get("inertia")) {
    b.inertia_B = inertia(*inertia_node, map.field("inertia"));
  } else if (shape_inertia) {
    b.inertia_B = *shape_inertia;
  } else {
    map.require("inertia", without_shape);
  }

  if (auto payload = map.get("payload")) add_payload(*payload, map.field("payload"), b);

  const double coordinate_scale = b.joint == JointType::revolute ? angle_scale_ : 1.0;
  if (auto z0 = map.get("z0")) {
    b.z0 = number(*z0, map.field("z0")) * coordinate_scale;
    if (b.joint == JointType::prismatic) bounded(b.z0, *z0, map.field("z0"), kMaxLength, "m");
  }
  if (auto zd0 = map.get("zd0")) b.zd0 = number(*zd0, map.field("zd0")) * coordinate_scale;
  return raw;
}

// A load the body carries (a bucket's soil, a crane's hook load): `mass`
// (kg, >= 0) whose centre is `at` (body frame) and, with `size`, a uniform
// box of those sides about it (a point mass without). The body's mass,
// centre of mass and inertia become the pair's; its own `mass`, `com` and
// `inertia` stay the empty body's, so that bodies/NAME/payload/mass is the
// load alone, a parameter that moves the body's first moment and inertia
// about its origin linearly (hosts/common/parameter_direction.cpp).
void Parser::add_payload(const YAML::Node& node, const std::string& field, Body& b) const {
  const MapView payload(*this, node, field, {"mass", "at", "size"});
  const YAML::Node mass_node = payload.require("mass", "the load's mass (kg, 0 for none)");
  const double m = bounded(non_negative(mass_node, payload.field("mass")), mass_node,
                           payload.field("mass"), kMaxMass, "kg");
  const Eigen::Vector3d at = length3(
      payload.require("at", "[x, y, z]: the load's centre in the body frame"), payload.field("at"));
  Eigen::Matrix3d own = Eigen::Matrix3d::Zero();
  if (auto size_node = payload.get("size")) {
    const Eigen::Vector3d d = length3(*size_node, payload.field("size"));
    if (!(d.minCoeff() > 0.0))
      fail(*size_node, payload.field("size"), "expected three positive sides [x, y, z] (m)");
    own = box_inertia(m, d);
  }
  if (m == 0.0) return;  // no load: the body as written, to the bit
  // Both inertias moved to the pair's centre of mass (parallel axes).
  const auto about = [](double mass, const Eigen::Vector3d& d) {
    return Eigen::Matrix3d(mass *
                           (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()));
  };
  const double total = b.mass + m;
  const Eigen::Vector3d com = (b.mass * b.com_B + m * at) / total;
  b.inertia_B = b.inertia_B + about(b.mass, b.com_B - com) + own + about(m, at - com);
  b.com_B = com;
  b.mass = total;
}

// Planar: every revolute axis along Z, every prismatic axis in the plane,
// every fixed orientation a rotation about Z.
void Parser::check_planar(const ModelFile& file) {
  planar_ = true;
  for (std::size_t i = 0; i < file.model.bodies.size(); ++i) {
    const Body& b = file.model.bodies[i];
    const bool ok_axis = b.joint == JointType::revolute ? std::abs(b.axis_P.z()) > 1.0 - 1e-9
                                                        : std::abs(b.axis_P.z()) < 1e-9;
    const bool ok_orientation = std::abs(b.R_P_B0(2, 2) - 1.0) < 1e-9;
    if (!ok_axis || !ok_orientation)
      throw InputError(file.body_marks[i], "bodies '" + b.name + "'",
                       ok_axis ? "expected a fixed orientation about Z in a planar model"
                               : "expected a joint axis along Z (revolute) or in the XY "
                                 "plane (prismatic) in a planar model");
  }
}

}  // namespace mh::model_file_detail
