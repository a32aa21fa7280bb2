#include "mechanism_drawing.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "monohydra/core/data.hpp"
#include "monohydra/core/kinematics.hpp"
#include "svg_plot.hpp"

namespace mh::cli {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kWidth = 820.0;
constexpr double kMaxDrawingHeight = 560.0;
constexpr double kMargin = 24.0;
constexpr double kTitleHeight = 30.0;
constexpr double kLegendRow = 18.0;
constexpr double kMaxPanelHeight = 330.0;  // each view of a 3D model
constexpr double kViewCaption = 20.0;
constexpr double kViewGap = 14.0;

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f", v);
  return buf;
}

// Linear blend of two colours "#rrggbb", f in [0, 1].
std::string blend(unsigned from, unsigned to, double f) {
  auto channel = [&](int shift) {
    const double a = (from >> shift) & 0xffu, b = (to >> shift) & 0xffu;
    return static_cast<unsigned>(std::lround(a + (b - a) * f));
  };
  char buf[8];
  std::snprintf(buf, sizeof(buf), "#%02x%02x%02x", channel(16), channel(8), channel(0));
  return buf;
}

constexpr unsigned kBodyFirst = 0xb7c9e2, kBodyLast = 0x1f3b73;
constexpr unsigned kElementFirst = 0xf8d5ad, kElementLast = 0xc0600b;

// What is drawn of each body, fixed by the model.
struct BodySketch {
  std::vector<int> children;       // their joint points
  std::vector<Vector3d> points_B;  // cut-joint and subsystem points, beam end
  double square_side = 0.0;        // > 0: drawn as a square about the joint point
};

struct Sketch {
  std::vector<BodySketch> bodies;
  std::vector<Vector3d> ground_points;  // joints, cut joints and subsystems on the ground
  struct Guide {
    Vector3d point;
    Vector3d axis;
  };
  std::vector<Guide> guides;  // translational cut joints sliding on the ground
  struct Element {
    std::string name;
    std::vector<BodyPoint> points;
  };
  std::vector<Element> elements;  // subsystems with points
};

Sketch sketch_of(const ModelFile& file) {
  const Model& m = file.model;
  Sketch s;
  s.bodies.resize(m.bodies.size());
  auto on = [&s](const BodyPoint& p) {
    if (p.body == kGround)
      s.ground_points.push_back(p.p_B);
    else
      s.bodies[static_cast<size_t>(p.body)].points_B.push_back(p.p_B);
  };
  for (size_t j = 0; j < m.bodies.size(); ++j) {
    const Body& b = m.bodies[j];
    if (b.parent == kGround)
      s.ground_points.push_back(b.joint_P);
    else
      s.bodies[static_cast<size_t>(b.parent)].children.push_back(static_cast<int>(j));
    BodySketch& bs = s.bodies[j];
    if (b.com_B.norm() > 1e-9) {
      // A beam from its joint point through its centre of mass: the far end
      // of a uniform beam.
      bs.points_B.push_back(2.0 * b.com_B);
    } else if (b.mass > 0.0 && b.inertia_B(2, 2) > 0.0) {
      // Centred on the joint point: the cube with the body's inertia about Z
      // (m L^2 / 6 for a cuboid of side L).
      bs.square_side = std::sqrt(6.0 * b.inertia_B(2, 2) / b.mass);
    }
  }
  for (const CutJoint& c : m.cut_joints) {
    on(c.a);
    on(c.b);
    if (c.type == CutJointType::translational) {
      if (c.a.body == kGround) s.guides.push_back({c.a.p_B, c.axis_a});
      if (c.b.body == kGround) s.guides.push_back({c.b.p_B, c.axis_b});
    }
  }
  for (const SubsystemSpec& sub : file.subsystems) {
    Sketch::Element e;
    e.name = sub.name;
    for (const auto& [key, p] : sub.points) {
      on(p.point);
      e.points.push_back(p.point);
    }
    if (!e.points.empty()) s.elements.push_back(e);
  }
  return s;
}

// A projection of the world on the drawing: screen right and up.
struct View {
  std::string name;  // "" for the single view of a planar model
  Eigen::Matrix<double, 2, 3> P;
};

// A planar model: its XY plane. A 3D one: side and top views and an
// isometric one, "up" against gravity (Y without gravity), the side view's
// horizontal the world axis most nearly level.
std::vector<View> views_of(const Model& m) {
  Eigen::Matrix<double, 2, 3> xy;
  xy << 1, 0, 0, 0, 1, 0;
  if (m.planar) return {View{"", xy}};
  const ViewAxes a = view_axes(m);
  const Vector3d &up = a.up, &h1 = a.h1, &h2 = a.h2, &eye = a.iso_eye;
  const Vector3d right = up.cross(eye).normalized();
  Eigen::Matrix<double, 2, 3> side, top, iso;
  side << h1.transpose(), up.transpose();
  top << h1.transpose(), h2.transpose();
  iso << right.transpose(), eye.cross(right).transpose();
  return {View{"side view", side}, View{"top view", top}, View{"isometric view", iso}};
}

// The world positions of one frame, projected by a view.
struct FrameShape {
  std::vector<std::pair<Vector2d, Vector2d>> beams;
  std::vector<std::vector<Vector2d>> squares;
  std::vector<Vector2d> joints;      // body joint points
  std::vector<Vector2d> cut_points;  // revolute/spherical: circles
  std::vector<std::vector<Vector2d>> elements;
};

FrameShape shape_of(const Model& m, const Sketch& s, Data& data, const Eigen::VectorXd& z,
                    const View& view) {
  FrameShape f;
  forward_kinematics(m, data, z, Eigen::VectorXd::Zero(z.size()));
  auto xy = [&view](const Vector3d& v) { return Vector2d(view.P * v); };
  for (size_t j = 0; j < m.bodies.size(); ++j) {
    const BodySketch& bs = s.bodies[j];
    const Vector2d o = xy(data.o_W[j]);
    f.joints.push_back(o);
    for (int c : bs.children) f.beams.emplace_back(o, xy(data.o_W[static_cast<size_t>(c)]));
    for (const Vector3d& p : bs.points_B)
      f.beams.emplace_back(o, xy(point_position(data, BodyPoint{static_cast<int>(j), p})));
    if (bs.square_side > 0.0) {
      const double h = bs.square_side / 2.0;
      std::vector<Vector2d> corners;
      for (const auto& c :
           {Vector3d(-h, -h, 0), Vector3d(h, -h, 0), Vector3d(h, h, 0), Vector3d(-h, h, 0)})
        corners.push_back(xy(data.o_W[j] + data.R_W_B[j] * c));
      f.squares.push_back(corners);
    }
  }
  for (const CutJoint& c : m.cut_joints)
    if (c.type != CutJointType::translational)
      f.cut_points.push_back(xy(point_position(data, c.a)));
  for (const auto& e : s.elements) {
    std::vector<Vector2d> pts;
    for (const BodyPoint& p : e.points) pts.push_back(xy(point_position(data, p)));
    f.elements.push_back(pts);
  }
  return f;
}

}  // namespace

ViewAxes view_axes(const Model& m) {
  ViewAxes a;
  a.up = m.gravity.norm() > 0.0 ? Vector3d(-m.gravity.normalized()) : Vector3d::UnitY();
  Vector3d level = Vector3d::UnitX();
  for (int k = 1; k < 3; ++k)
    if (std::abs(a.up[k]) < std::abs(level.dot(a.up)) - 1e-12) level = Vector3d::Unit(k);
  a.h1 = (level - level.dot(a.up) * a.up).normalized();
  a.h2 = a.up.cross(a.h1);
  a.iso_eye = (a.h1 - a.h2 + a.up).normalized();
  return a;
}

std::vector<MechanismFrame> frames_every_second(const RunRecord& run) {
  std::vector<MechanismFrame> frames;
  const size_t rows = run.rows();
  if (rows == 0) return frames;
  const auto& t = run.values("t");
  const double t_last = t.back();
  std::vector<size_t> picks;
  if (t_last >= 2.0) {
    size_t k = 0;
    const long last_second = static_cast<long>(std::floor(t_last + 1e-9));
    for (long s = 0; s <= last_second; ++s) {
      const double second = static_cast<double>(s);
      while (k + 1 < rows && std::abs(t[k + 1] - second) <= std::abs(t[k] - second)) ++k;
      picks.push_back(k);
    }
  } else {
    for (int i = 0; i < 5; ++i)
      picks.push_back(static_cast<size_t>(std::lround(i / 4.0 * static_cast<double>(rows - 1))));
  }
  picks.erase(std::unique(picks.begin(), picks.end()), picks.end());
  for (size_t k : picks) {
    MechanismFrame f;
    f.t = t[k];
    f.z.resize(run.num_coordinates);
    for (int j = 0; j < run.num_coordinates; ++j)
      f.z[j] = run.columns[1 + static_cast<size_t>(j)][k];
    frames.push_back(f);
  }
  return frames;
}

std::string svg_mechanism(const ModelFile& file, const std::vector<MechanismFrame>& frames,
                          const std::string& id, const std::string& title) {
  const Model& m = file.model;
  const Sketch sketch = sketch_of(file);
  const std::vector<View> views = views_of(m);
  const bool captions = views.size() > 1;
  const double max_h = captions ? kMaxPanelHeight : kMaxDrawingHeight;
  Data data(m);

  std::ostringstream panels;
  double top = kTitleHeight;
  for (size_t v = 0; v < views.size(); ++v) {
    const View& view = views[v];
    auto project = [&view](const Vector3d& p) { return Vector2d(view.P * p); };
    std::vector<FrameShape> shapes;
    shapes.reserve(frames.size());
    for (const auto& fr : frames) shapes.push_back(shape_of(m, sketch, data, fr.z, view));

    // Bounds of everything drawn.
    double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
    auto grow = [&](const Vector2d& p) {
      x0 = std::min(x0, p.x());
      x1 = std::max(x1, p.x());
      y0 = std::min(y0, p.y());
      y1 = std::max(y1, p.y());
    };
    for (const auto& p : sketch.ground_points) grow(project(p));
    for (const auto& f : shapes) {
      for (const auto& b : f.beams) {
        grow(b.first);
        grow(b.second);
      }
      for (const auto& sq : f.squares)
        for (const auto& p : sq) grow(p);
      for (const auto& p : f.joints) grow(p);
      for (const auto& e : f.elements)
        for (const auto& p : e) grow(p);
    }
    if (!(x1 >= x0)) x0 = y0 = -1.0, x1 = y1 = 1.0;
    const double span = std::max({x1 - x0, y1 - y0, 1e-3});
    const double pad = 0.06 * span;
    x0 -= pad, x1 += pad, y0 -= pad, y1 += pad;
    if (captions) {
      panels << "<text class=\"view\" x=\"" << num(kMargin) << "\" y=\"" << num(top + 14)
             << "\" font-style=\"italic\">" << xml_escape(view.name) << "</text>\n";
      top += kViewCaption;
    }
    const double avail_w = kWidth - 2.0 * kMargin;
    const double scale = std::min(avail_w / (x1 - x0), max_h / (y1 - y0));
    const double draw_w = (x1 - x0) * scale, draw_h = (y1 - y0) * scale;
    const double left = (kWidth - draw_w) / 2.0;
    auto sx = [&](double x) { return num(left + (x - x0) * scale); };
    auto sy = [&](double y) { return num(top + (y1 - y) * scale); };
    auto pt = [&](const Vector2d& p) { return sx(p.x()) + "," + sy(p.y()); };
    const std::string clip = id + (captions ? "-clip" + std::to_string(v) : "-clip");

    panels << "<defs><clipPath id=\"" << xml_escape(clip) << "\"><rect x=\"" << num(left)
           << "\" y=\"" << num(top) << "\" width=\"" << num(draw_w) << "\" height=\"" << num(draw_h)
           << "\"/></clipPath></defs>\n";
    // The guides of sliders on the ground, under everything.
    panels << "<g class=\"ground\" clip-path=\"url(#" << xml_escape(clip) << ")\">\n";
    const double reach = 2.0 * std::hypot(x1 - x0, y1 - y0);
    for (const auto& g : sketch.guides) {
      const Vector2d p = project(g.point);
      Vector2d a = project(g.axis);
      if (a.norm() < 1e-12) continue;
      a.normalize();
      panels << "<line class=\"guide\" x1=\"" << sx((p - reach * a).x()) << "\" y1=\""
             << sy((p - reach * a).y()) << "\" x2=\"" << sx((p + reach * a).x()) << "\" y2=\""
             << sy((p + reach * a).y()) << "\" stroke=\"#777777\" stroke-width=\"1\""
             << " stroke-dasharray=\"6 4\"/>\n";
    }
    panels << "</g>\n";

    for (size_t i = 0; i < shapes.size(); ++i) {
      const FrameShape& f = shapes[i];
      const double k = shapes.size() > 1
                           ? static_cast<double>(i) / (static_cast<double>(shapes.size()) - 1.0)
                           : 1.0;
      const std::string body = blend(kBodyFirst, kBodyLast, k);
      const std::string element = blend(kElementFirst, kElementLast, k);
      char t_text[32];
      std::snprintf(t_text, sizeof(t_text), "%g", frames[i].t);
      panels << "<g class=\"frame\" data-t=\"" << t_text << "\">\n<title>t = " << t_text
             << " s</title>\n";
      for (const auto& e : f.elements) {
        if (e.size() == 2)
          panels << "<line class=\"element\" x1=\"" << sx(e[0].x()) << "\" y1=\"" << sy(e[0].y())
                 << "\" x2=\"" << sx(e[1].x()) << "\" y2=\"" << sy(e[1].y()) << "\" stroke=\""
                 << element
                 << "\" stroke-width=\"5\" stroke-linecap=\"round\" opacity=\"0.85\"/>\n";
        for (const auto& p : e)
          panels << "<circle class=\"element-point\" cx=\"" << sx(p.x()) << "\" cy=\"" << sy(p.y())
                 << "\" r=\"3.5\" fill=\"" << element << "\"/>\n";
      }
      for (const auto& sq : f.squares) {
        panels << "<polygon class=\"body\" points=\"";
        for (size_t c = 0; c < sq.size(); ++c) panels << (c ? " " : "") << pt(sq[c]);
        panels << "\" fill=\"" << body << "\" fill-opacity=\"0.35\" stroke=\"" << body
               << "\" stroke-width=\"2\"/>\n";
      }
      for (const auto& b : f.beams)
        panels << "<line class=\"body\" x1=\"" << sx(b.first.x()) << "\" y1=\"" << sy(b.first.y())
               << "\" x2=\"" << sx(b.second.x()) << "\" y2=\"" << sy(b.second.y()) << "\" stroke=\""
               << body << "\" stroke-width=\"3\" stroke-linecap=\"round\"/>\n";
      for (const auto& p : f.joints)
        panels << "<circle class=\"joint\" cx=\"" << sx(p.x()) << "\" cy=\"" << sy(p.y())
               << "\" r=\"3\" fill=\"#ffffff\" stroke=\"" << body << "\" stroke-width=\"1.5\"/>\n";
      for (const auto& p : f.cut_points)
        panels << "<circle class=\"cut-joint\" cx=\"" << sx(p.x()) << "\" cy=\"" << sy(p.y())
               << "\" r=\"4.5\" fill=\"none\" stroke=\"" << body << "\" stroke-width=\"1.5\"/>\n";
      panels << "</g>\n";
    }

    // A grey triangle under each ground point, on top: the bodies would hide it.
    panels << "<g class=\"ground\" fill=\"#999999\" stroke=\"#555555\">\n";
    for (const auto& g3 : sketch.ground_points) {
      const Vector2d g = project(g3);
      const double cx = left + (g.x() - x0) * scale, cy = top + (y1 - g.y()) * scale;
      panels << "<polygon points=\"" << num(cx) << ',' << num(cy) << ' ' << num(cx - 7) << ','
             << num(cy + 11) << ' ' << num(cx + 7) << ',' << num(cy + 11) << "\"/>\n";
    }
    panels << "</g>\n";
    top += draw_h + (captions ? kViewGap : 0.0);
  }

  const size_t legend_items = frames.size() + sketch.elements.size();
  const size_t per_row = 8;
  const double legend_top = top + 22.0;
  const size_t legend_rows = (legend_items + per_row - 1) / per_row;
  const double height = legend_top + kLegendRow * static_cast<double>(legend_rows) + 6.0;

  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"" << xml_escape(id)
    << "\" class=\"mechanism\" width=\"" << num(kWidth) << "\" height=\"" << num(height)
    << "\" viewBox=\"0 0 " << num(kWidth) << ' ' << num(height)
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  o << "<title>" << xml_escape(title) << "</title>\n";
  o << "<rect x=\"0\" y=\"0\" width=\"" << num(kWidth) << "\" height=\"" << num(height)
    << "\" fill=\"#ffffff\"/>\n";
  o << "<text x=\"" << num(kWidth / 2) << "\" y=\"18\" text-anchor=\"middle\" font-weight=\"bold\">"
    << xml_escape(title) << "</text>\n";
  o << panels.str();

  // Legend: one entry per frame time, then the elements.
  o << "<g class=\"legend\">\n";
  const double item_w = (kWidth - 2.0 * kMargin) / static_cast<double>(per_row);
  for (size_t i = 0; i < legend_items; ++i) {
    const double x = kMargin + item_w * static_cast<double>(i % per_row);
    const size_t legend_row = i / per_row;
    const double y = legend_top + kLegendRow * static_cast<double>(legend_row);
    std::string colour, label;
    if (i < frames.size()) {
      const double k = frames.size() > 1
                           ? static_cast<double>(i) / (static_cast<double>(frames.size()) - 1.0)
                           : 1.0;
      colour = blend(kBodyFirst, kBodyLast, k);
      char buf[32];
      std::snprintf(buf, sizeof(buf), "t = %g s", frames[i].t);
      label = buf;
    } else {
      colour = blend(kElementFirst, kElementLast, 1.0);
      label = sketch.elements[i - frames.size()].name;
    }
    o << "<line x1=\"" << num(x) << "\" y1=\"" << num(y - 4) << "\" x2=\"" << num(x + 22)
      << "\" y2=\"" << num(y - 4) << "\" stroke=\"" << colour << "\" stroke-width=\"4\"/>\n"
      << "<text x=\"" << num(x + 28) << "\" y=\"" << num(y) << "\">" << xml_escape(label)
      << "</text>\n";
  }
  o << "</g>\n</svg>\n";
  return o.str();
}

}  // namespace mh::cli
