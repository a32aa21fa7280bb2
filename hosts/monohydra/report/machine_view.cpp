#include "machine_view.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "mechanism_drawing.hpp"
#include "monohydra/core/data.hpp"
#include "monohydra/core/kinematics.hpp"
#include "view_scripts.hpp"

namespace mh::cli {
namespace {

using Eigen::Vector3d;

// A number for the page: `digits` significant digits, "null" when not finite.
void put(std::ostringstream& o, double v, int digits = 5) {
  if (!std::isfinite(v)) {
    o << "null";
    return;
  }
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*g", digits, v);
  o << buf;
}

void put3(std::ostringstream& o, const Vector3d& v) {
  o << '[';
  put(o, v.x());
  o << ',';
  put(o, v.y());
  o << ',';
  put(o, v.z());
  o << ']';
}

// A JSON array of points.
void put_points(std::ostringstream& o, const std::vector<Vector3d>& points) {
  o << '[';
  for (size_t k = 0; k < points.size(); ++k) {
    o << (k ? "," : "");
    put3(o, points[k]);
  }
  o << ']';
}

// A JSON string that can sit inside <script> and a CDATA section: '<', '>'
// and '&' as \u escapes, so no "</script" or "]]>" can appear.
void put_string(std::ostringstream& o, const std::string& s) {
  o << '"';
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      o << '\\' << c;
    } else if (u < 0x20 || c == '<' || c == '>' || c == '&') {
      char buf[8];
      std::snprintf(buf, sizeof(buf), "\\u%04x", u);
      o << buf;
    } else {
      o << c;
    }
  }
  o << '"';
}

// Numbers separated by commas, for a JSON array.
struct NumberList {
  std::ostringstream text;
  bool empty = true;
  void add(double v, int digits) {
    if (!empty) text << ',';
    empty = false;
    put(text, v, digits);
  }
  std::string str() const { return text.str(); }
};

// What the view draws between two points when a component declared no look.
struct Part {
  std::string name;
  std::string kind;  // "actuator", "link", "line" (undeclared, two points), "dot" (one point)
  BodyPoint a, b;
  double barrel_length = 0.0, barrel_diameter = 0.0, rod_diameter = 0.0;
  int column_a = -1, column_b = -1;  // per run: result columns colouring it
  std::string state_a, state_b;      // their names
};

std::vector<Part> parts_of(const ModelFile& file, const ViewDeclarations& declared) {
  std::vector<Part> parts;
  auto column = [&declared](int state) {
    return state >= 0 && static_cast<size_t>(state) < declared.state_columns.size()
               ? declared.state_columns[static_cast<size_t>(state)]
               : std::string();
  };
  for (const Visual& v : declared.visuals) {
    Part p;
    p.name = v.instance;
    p.kind = v.kind == Visual::Kind::actuator ? "actuator" : "link";
    p.a = v.a;
    p.b = v.b;
    p.barrel_length = v.barrel_length;
    p.barrel_diameter = v.barrel_diameter;
    p.rod_diameter = v.rod_diameter;
    p.state_a = column(v.state_a);
    p.state_b = column(v.state_b);
    parts.push_back(p);
  }
  // Components that declared nothing: a line through their points in key
  // order, or a dot at a single point.
  for (const SubsystemSpec& sub : file.subsystems) {
    const bool declared_look =
        std::any_of(declared.visuals.begin(), declared.visuals.end(),
                    [&sub](const Visual& v) { return v.instance == sub.name; });
    if (declared_look || sub.points.empty()) continue;
    std::vector<BodyPoint> pts;
    for (const auto& [key, spec] : sub.points) pts.push_back(spec.point);
    if (pts.size() == 1) {
      Part p;
      p.name = sub.name;
      p.kind = "dot";
      p.a = p.b = pts.front();
      parts.push_back(p);
      continue;
    }
    for (size_t k = 0; k + 1 < pts.size(); ++k) {
      Part p;
      p.name = sub.name;
      p.kind = "line";
      p.a = pts[k];
      p.b = pts[k + 1];
      parts.push_back(p);
    }
  }
  return parts;
}

// The rows shown: one per 1/fps of simulated time (the nearest row), the
// first and the last row always.
std::vector<size_t> frame_rows(const RunRecord& run, double fps) {
  const auto& t = run.values("t");
  std::vector<size_t> rows;
  if (t.empty()) return rows;
  const double t0 = t.front(), t1 = t.back();
  const long frames = std::max(1L, std::lround(std::floor((t1 - t0) * fps + 1e-9)));
  size_t k = 0;
  for (long f = 0; f <= frames; ++f) {
    const double target = std::min(t1, t0 + static_cast<double>(f) / fps);
    while (k + 1 < t.size() && std::abs(t[k + 1] - target) <= std::abs(t[k] - target)) ++k;
    if (rows.empty() || rows.back() != k) rows.push_back(k);
  }
  if (rows.back() != t.size() - 1) rows.push_back(t.size() - 1);
  return rows;
}

Eigen::VectorXd coordinates_at(const RunRecord& run, size_t row) {
  Eigen::VectorXd z(run.num_coordinates);
  for (int j = 0; j < run.num_coordinates; ++j) z[j] = run.columns[1 + static_cast<size_t>(j)][row];
  return z;
}

// The body points worth following, in body frames: beam and cylinder ends,
// child joints, cut-joint and component points, a beam's far end from its
// centre of mass.
std::vector<BodyPoint> candidate_points(const ModelFile& file) {
  const Model& m = file.model;
  std::vector<BodyPoint> pts;
  for (size_t j = 0; j < m.bodies.size(); ++j) {
    const int body = static_cast<int>(j);
    const Body& b = m.bodies[j];
    if (b.parent != kGround) pts.push_back({b.parent, b.joint_P});
    if (b.com_B.norm() > 1e-9) pts.push_back({body, 2.0 * b.com_B});
    if (j < file.body_shapes.size()) {
      const BodyShape& s = file.body_shapes[j];
      if (s.kind == BodyShape::Kind::beam || s.kind == BodyShape::Kind::cylinder)
        pts.push_back({body, Vector3d(s.size.x(), 0.0, 0.0)});
    }
  }
  for (const CutJoint& c : m.cut_joints)
    for (const BodyPoint& p : {c.a, c.b})
      if (p.body != kGround) pts.push_back(p);
  for (const SubsystemSpec& sub : file.subsystems)
    for (const auto& [key, spec] : sub.points)
      if (spec.point.body != kGround) pts.push_back(spec.point);
  return pts;
}

// Each body's bones (for a body without a shape): from its joint point to
// every other point it carries.
std::vector<std::vector<Vector3d>> bones_of(const ModelFile& file) {
  const Model& m = file.model;
  std::vector<std::vector<Vector3d>> bones(m.bodies.size());
  for (const BodyPoint& p : candidate_points(file))
    if (p.body != kGround && p.p_B.norm() > 1e-9) {
      auto& list = bones[static_cast<size_t>(p.body)];
      const bool seen = std::any_of(list.begin(), list.end(),
                                    [&p](const Vector3d& q) { return (q - p.p_B).norm() < 1e-9; });
      if (!seen) list.push_back(p.p_B);
    }
  return bones;
}

}  // namespace

ViewDeclarations view_declarations(const ModelFile& file, const PluginRegistry& registry,
                                   const std::vector<std::string>& formulations) {
  ViewDeclarations out;
  std::vector<std::string> tries = formulations;
  if (tries.empty()) tries.emplace_back();
  for (const auto& f : tries) {
    try {
      RunChoices choices;
      choices.formulation = f;
      const Simulation sim(file, registry, choices);
      out.visuals = sim.visuals();
      out.state_columns = sim.state_names();
      out.note.clear();
      return out;
    } catch (const std::exception& err) {
      out.note = err.what();
    }
  }
  return out;
}

std::string machine_view_data(const ModelFile& file, const ViewDeclarations& declared,
                              const std::vector<const RunRecord*>& runs_in,
                              double frames_per_second) {
  const Model& m = file.model;
  std::vector<const RunRecord*> runs;
  for (const RunRecord* r : runs_in)
    if (r != nullptr && r->rows() > 0 && r->num_coordinates == static_cast<int>(m.bodies.size()))
      runs.push_back(r);
  if (runs.empty()) throw std::invalid_argument("the 3D view needs a run with rows");
  const std::vector<Part> parts = parts_of(file, declared);
  Data data(m);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(m.bodies.size()));

  std::ostringstream o;
  o << "window.MH_VIEW={\"version\":1,\"planar\":" << (m.planar ? "true" : "false");
  const ViewAxes axes = view_axes(m);  // mechanism_drawing.hpp
  o << ",\"up\":";
  put3(o, axes.up);
  // The first view's direction (towards the eye): a planar model from +Z as
  // the paper draws it, a little from above; a 3D one isometric, as the 2D
  // drawing's third view.
  o << ",\"eye\":";
  put3(o, m.planar ? Vector3d((Vector3d::UnitZ() + 0.3 * axes.up).normalized()) : axes.iso_eye);

  // Bodies: shape, bones, joint axis in the body frame.
  const auto bones = bones_of(file);
  o << ",\"bodies\":[";
  for (size_t j = 0; j < m.bodies.size(); ++j) {
    const Body& b = m.bodies[j];
    const BodyShape shape = j < file.body_shapes.size() ? file.body_shapes[j] : BodyShape{};
    o << (j ? "," : "") << "{\"name\":";
    put_string(o, b.name);
    o << ",\"shape\":\"" << to_string(shape.kind) << "\",\"size\":";
    put3(o, shape.size);
    o << ",\"at\":";
    put3(o, shape.at);
    o << ",\"com\":";
    put3(o, b.com_B);
    o << ",\"bones\":";
    put_points(o, bones[j]);
    o << ",\"joint\":\"" << (b.joint == JointType::revolute ? "revolute" : "prismatic")
      << "\",\"axis\":";
    // A revolute axis is fixed in the body too (the rotation is about it).
    put3(o, b.R_P_B0.transpose() * b.axis_P);
    o << '}';
  }
  o << ']';

  // Fixed points on the ground, and cut joints (drawn at their point a).
  std::vector<Vector3d> ground;
  for (const Body& b : m.bodies)
    if (b.parent == kGround) ground.push_back(b.joint_P);
  for (const CutJoint& c : m.cut_joints)
    for (const BodyPoint& p : {c.a, c.b})
      if (p.body == kGround) ground.push_back(p.p_B);
  for (const SubsystemSpec& sub : file.subsystems)
    for (const auto& [key, spec] : sub.points)
      if (spec.point.body == kGround) ground.push_back(spec.point.p_B);
  o << ",\"ground\":";
  put_points(o, ground);
  o << ",\"cuts\":[";
  for (size_t k = 0; k < m.cut_joints.size(); ++k) {
    const CutJoint& c = m.cut_joints[k];
    o << (k ? "," : "") << "{\"name\":";
    put_string(o, c.name);
    o << ",\"body\":" << c.a.body << ",\"p\":";
    put3(o, c.a.p_B);
    o << ",\"type\":\""
      << (c.type == CutJointType::revolute    ? "revolute"
          : c.type == CutJointType::spherical ? "spherical"
                                              : "translational")
      << "\"}";
  }
  o << ']';

  // Parts and the columns that colour them, in each run.
  o << ",\"parts\":[";
  for (size_t k = 0; k < parts.size(); ++k) {
    const Part& p = parts[k];
    o << (k ? "," : "") << "{\"name\":";
    put_string(o, p.name);
    o << ",\"kind\":\"" << p.kind << "\",\"barrel_length\":";
    put(o, p.barrel_length);
    o << ",\"barrel_diameter\":";
    put(o, p.barrel_diameter);
    o << ",\"rod_diameter\":";
    put(o, p.rod_diameter);
    o << ",\"columns\":[";
    put_string(o, p.state_a);
    o << ',';
    put_string(o, p.state_b);
    o << "]}";
  }
  o << ']';

  // The colour scale: every colouring column's range over every run.
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  std::string unit;
  for (const RunRecord* r : runs)
    for (const Part& p : parts)
      for (const std::string& name : {p.state_a, p.state_b}) {
        const int c = name.empty() ? -1 : r->column(name);
        if (c < 0) continue;
        if (unit.empty()) unit = r->units[static_cast<size_t>(c)];
        for (double v : r->columns[static_cast<size_t>(c)])
          if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
      }
  o << ",\"scale\":";
  if (hi >= lo) {
    if (hi - lo < 1e-12 * std::max(1.0, std::abs(hi))) hi = lo + 1.0;
    o << "{\"unit\":";
    put_string(o, unit);
    o << ",\"min\":";
    put(o, lo, 6);
    o << ",\"max\":";
    put(o, hi, 6);
    o << '}';
  } else {
    o << "null";
  }

  // The marker: the candidate point that travels farthest in the first run,
  // so that a test (or a reader) can follow one point from the CSV to the
  // screen.
  const RunRecord& first = *runs.front();
  const std::vector<size_t> first_rows = frame_rows(first, frames_per_second);
  const std::vector<BodyPoint> candidates = candidate_points(file);
  BodyPoint marker{kGround, Vector3d::Zero()};
  if (!candidates.empty()) {
    std::vector<double> travel(candidates.size(), 0.0);
    std::vector<Vector3d> last(candidates.size());
    for (size_t f = 0; f < first_rows.size(); ++f) {
      forward_kinematics(m, data, coordinates_at(first, first_rows[f]), zero);
      for (size_t c = 0; c < candidates.size(); ++c) {
        const Vector3d p = point_position(data, candidates[c]);
        if (f > 0) travel[c] += (p - last[c]).norm();
        last[c] = p;
      }
    }
    marker = candidates[static_cast<size_t>(std::max_element(travel.begin(), travel.end()) -
                                            travel.begin())];
  }
  o << ",\"marker\":{\"body\":" << marker.body << ",\"p\":";
  put3(o, marker.p_B);
  o << '}';

  // The frames of each run: t; per body position and quaternion (x, y, z, w);
  // per part its two points' world positions and its two colouring values.
  o << ",\"runs\":[";
  for (size_t r = 0; r < runs.size(); ++r) {
    const RunRecord& run = *runs[r];
    const std::vector<size_t> rows = frame_rows(run, frames_per_second);
    const auto& t = run.values("t");
    std::vector<int> colour_columns;
    for (const Part& p : parts)
      for (const std::string& name : {p.state_a, p.state_b})
        colour_columns.push_back(name.empty() ? -1 : run.column(name));
    NumberList times, poses, points, values;
    for (const size_t row : rows) {
      forward_kinematics(m, data, coordinates_at(run, row), zero);
      times.add(t[row], 8);
      for (size_t j = 0; j < m.bodies.size(); ++j) {
        const Eigen::Quaterniond q(data.R_W_B[j]);
        for (int i = 0; i < 3; ++i) poses.add(data.o_W[j][i], 6);
        for (const double c : {q.x(), q.y(), q.z(), q.w()}) poses.add(c, 6);
      }
      for (size_t k = 0; k < parts.size(); ++k) {
        for (const BodyPoint& bp : {parts[k].a, parts[k].b}) {
          const Vector3d x = point_position(data, bp);
          for (int i = 0; i < 3; ++i) points.add(x[i], 6);
        }
        for (size_t side = 0; side < 2; ++side) {
          const int c = colour_columns[2 * k + side];
          values.add(c < 0 ? std::nan("") : run.columns[static_cast<size_t>(c)][row], 4);
        }
      }
    }
    o << (r ? "," : "") << "{\"label\":";
    put_string(o, run.label.empty() ? run.formulation : run.label);
    o << ",\"t\":[" << times.str() << "],\"pose\":[" << poses.str() << "],\"points\":["
      << points.str() << "],\"values\":[" << values.str() << "]}";
  }
  o << "]};\n";
  return o.str();
}

bool machine_view_available() {
  return !three_js_source().empty();
}

std::string machine_view_html(const std::string& data_script) {
  if (!machine_view_available()) return "";
  auto script = [](std::string_view code) {
    // The pieces are checked once here: none may close its CDATA section or
    // its script element early.
    if (code.find("]]>") != std::string_view::npos ||
        code.find("</script") != std::string_view::npos)
      throw std::logic_error("a script of the 3D view holds ']]>' or '</script'");
    std::string s = "<script>//<![CDATA[\n";
    s.append(code.data(), code.size());
    s += "\n//]]></script>\n";
    return s;
  };
  std::string html =
      "<section id=\"view\" class=\"mh-view\">\n<h2>The machine in motion</h2>\n"
      "<div class=\"mh-view-box\"><canvas id=\"mh-view-canvas\" width=\"820\" height=\"520\" "
      "data-monohydra-view=\"loading\"></canvas></div>\n"
      "<div class=\"mh-controls\"><button type=\"button\" id=\"mh-play\">Pause</button>\n"
      "<input type=\"range\" id=\"mh-time\" min=\"0\" max=\"1000\" step=\"1\" value=\"0\"/>\n"
      "<span id=\"mh-time-text\">t = 0 s</span>\n"
      "<label>speed <select id=\"mh-speed\"><option value=\"0.1\">0.1x</option>"
      "<option value=\"0.25\">0.25x</option><option value=\"0.5\">0.5x</option>"
      "<option value=\"1\" selected=\"selected\">1x</option><option value=\"2\">2x</option>"
      "<option value=\"4\">4x</option></select></label>\n"
      "<label>solid <select id=\"mh-solid\"></select></label></div>\n"
      "<div class=\"mh-legend\" id=\"mh-legend\"></div>\n"
      "<p class=\"mh-caption\">Drag to orbit, right-drag (or shift-drag) to pan, scroll to zoom. "
      "The solid run is the one chosen above; the others are drawn as ghosts, so that where "
      "they part is seen. Chambers are coloured by their pressure on the legend's scale. "
      "The magenta dot follows the body point that travels farthest. A link to "
      "report.html#t=2.5 opens the view paused at t = 2.5 s (#t=end: the last frame).</p>\n"
      "<noscript><p>The 3D view needs JavaScript and WebGL.</p></noscript>\n</section>\n";
  html += script(three_js_source());
  html += script(orbit_controls_source());
  html += script(data_script);
  html += script(machine_view_source());
  return html;
}

void add_machine_view(ReportPage& page, const ModelFile& file, const PluginRegistry& registry,
                      const std::vector<const RunRecord*>& runs,
                      const std::vector<std::string>& formulations) {
  const bool any_rows = std::any_of(runs.begin(), runs.end(), [&file](const RunRecord* r) {
    return r != nullptr && r->rows() > 0 &&
           r->num_coordinates == static_cast<int>(file.model.bodies.size());
  });
  if (!machine_view_available()) {
    page.view_note =
        "This monohydra was built without three.js (Debian's libjs-three), so "
        "the report has no 3D view.";
    return;
  }
  if (file.model.bodies.empty() || !any_rows) {
    page.view_note = file.model.bodies.empty() ? "The model has no bodies to draw."
                                               : "No run has rows to animate.";
    return;
  }
  const ViewDeclarations declared = view_declarations(file, registry, formulations);
  const std::string data = machine_view_data(file, declared, runs);
  page.view = machine_view_html(data);
  char size[64];
  std::snprintf(size, sizeof(size), "%.2f MB", static_cast<double>(data.size()) / 1e6);
  page.facts.push_back(
      "3D view: " + std::to_string(runs.size()) + " run(s) at " +
      std::to_string(static_cast<int>(kViewFramesPerSecond)) +
      " frames per second of simulated time, " + size + " of frames" +
      (declared.note.empty() ? "" : " (components' looks unknown: " + declared.note + ")"));
}

}  // namespace mh::cli
