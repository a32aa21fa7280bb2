// YAML model files (docs/model-format.md): parse, validate, convert angles to
// radians and sort the bodies so that parents precede their children. Every
// problem becomes an InputError with the file, line, field and expectation.
#include "monohydra/core/model_file.hpp"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <queue>
#include <sstream>
#include <utility>

namespace mh {
namespace {

namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;
constexpr const char* kGroundName = "ground";
// Magnitudes beyond these are typos (a missing exponent sign, a unit slip):
// refused with the range rather than left to overflow the solver.
constexpr double kMaxMass = 1e12;   // kg, and kg m^2 for inertias
constexpr double kMaxLength = 1e6;  // m
constexpr std::uintmax_t kMaxFileBytes = 64u << 20;
// Result columns every run writes; a state, output or node may not take them.
const char* const kFixedColumns[] = {"t", "KE", "PE", "W", "drift", "phi_norm", "iters"};

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) {
    if (!out.empty()) out += ", ";
    out += item;
  }
  return out;
}

std::string format_number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

std::string format_vector(const Eigen::Vector3d& v) {
  return "[" + format_number(v.x()) + ", " + format_number(v.y()) + ", " + format_number(v.z()) +
         "]";
}

std::string child_field(const std::string& base, const std::string& key) {
  return base.empty() ? key : base + "." + key;
}

std::string index_field(const std::string& base, std::size_t index) {
  return base + "[" + std::to_string(index) + "]";
}

// What a node is, for "got ..." in messages.
std::string describe(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Scalar:
      return "'" + node.Scalar() + "'";
    case YAML::NodeType::Sequence:
      return node.size() == 1 ? "a list of 1 item"
                              : "a list of " + std::to_string(node.size()) + " items";
    case YAML::NodeType::Map:
      return "a mapping";
    case YAML::NodeType::Null:
    case YAML::NodeType::Undefined:
    default:
      return "nothing";
  }
}

// A scalar written as a number: plain (not quoted) and fully parsed as a
// double. Accepts YAML's .inf/.nan spellings and "nan"/"inf" (to report them
// as non-finite rather than as non-numbers).
std::optional<double> scalar_number(const YAML::Node& node) {
  if (!node.IsScalar()) return std::nullopt;
  const std::string& tag = node.Tag();
  if (tag != "?" && tag != "tag:yaml.org,2002:float" && tag != "tag:yaml.org,2002:int") {
    return std::nullopt;  // quoted or explicitly tagged as something else: a string
  }
  std::string text = node.Scalar();
  if (text == ".inf" || text == ".Inf" || text == ".INF" || text == "+.inf" || text == "+.Inf" ||
      text == "+.INF") {
    return HUGE_VAL;
  }
  if (text == "-.inf" || text == "-.Inf" || text == "-.INF") return -HUGE_VAL;
  if (text == ".nan" || text == ".NaN" || text == ".NAN") return std::nan("");
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  if (begin != end && *begin == '+') {
    ++begin;
    if (begin != end && *begin == '-') return std::nullopt;
  }
  if (begin == end) return std::nullopt;
  double value = 0.0;
  const auto result = std::from_chars(begin, end, value);
  if (result.ec != std::errc() || result.ptr != end) return std::nullopt;
  return value;
}

struct Entry {
  std::string key;
  YAML::Node key_node;
  YAML::Node value;
};

class Parser;

// A mapping whose keys have been checked: no duplicates and, when a list of
// allowed keys is given, nothing else (typo protection).
class MapView {
 public:
  MapView(const Parser& parser, const YAML::Node& node, std::string field,
          const std::vector<std::string>& allowed);

  std::optional<YAML::Node> get(const std::string& key) const {
    const Entry* entry = find(key);
    if (entry == nullptr) return std::nullopt;
    return entry->value;
  }
  YAML::Node require(const std::string& key, const std::string& hint = "") const;
  const std::vector<Entry>& entries() const { return entries_; }
  const YAML::Node& node() const { return node_; }
  const std::string& field() const { return field_; }
  std::string field(const std::string& key) const { return child_field(field_, key); }

 private:
  const Entry* find(const std::string& key) const {
    for (const auto& entry : entries_) {
      if (entry.key == key) return &entry;
    }
    return nullptr;
  }

  const Parser& parser_;
  YAML::Node node_;
  std::string field_;
  std::vector<Entry> entries_;
};

// A body as written, before its parent is resolved.
struct RawBody {
  Body body;
  YAML::Node name_node;
  std::string parent_name;
  YAML::Node parent_node;
  SourceMark mark;
  std::string field;
};

class Parser {
 public:
  explicit Parser(std::string file) : file_(std::move(file)) {}

  SourceMark mark(const YAML::Node& node) const {
    SourceMark m;
    m.file = file_;
    if (!node.IsDefined()) return m;
    YAML::Mark ym = node.Mark();
    if (node.IsNull()) {
      for (const auto& [value, key_mark] : null_value_marks_) {
        if (value.is(node)) ym = key_mark;
      }
    }
    if (!ym.is_null() && ym.line >= 0) {
      m.line = ym.line + 1;
      m.column = ym.column >= 0 ? ym.column + 1 : 0;
    }
    return m;
  }

  // yaml-cpp marks an empty value ("mass:") at the token after it, often on
  // the next line; MapView records its key's mark here instead.
  void mark_null_value(const YAML::Node& value, const YAML::Node& key) const {
    null_value_marks_.emplace_back(value, key.Mark());
  }

  [[noreturn]] void fail(const YAML::Node& node, const std::string& field,
                         const std::string& expectation) const {
    throw InputError(mark(node), field, expectation);
  }

  // --- scalars -------------------------------------------------------------

  std::string string(const YAML::Node& node, const std::string& field) const {
    if (!node.IsScalar()) fail(node, field, "expected a string, got " + describe(node));
    return node.Scalar();
  }

  std::string name(const YAML::Node& node, const std::string& field) const {
    std::string text = string(node, field);
    if (text.empty()) fail(node, field, "expected a non-empty name");
    return text;
  }

  double checked_number(const YAML::Node& node, const std::string& field, const char* what,
                        const std::function<bool(double)>& ok) const {
    const std::optional<double> value = scalar_number(node);
    if (!value || !std::isfinite(*value) || !ok(*value)) {
      fail(node, field, std::string("expected ") + what + ", got " + describe(node));
    }
    return *value;
  }

  double number(const YAML::Node& node, const std::string& field) const {
    return checked_number(node, field, "a finite number", [](double) { return true; });
  }
  double positive(const YAML::Node& node, const std::string& field) const {
    return checked_number(node, field, "a positive finite number", [](double v) { return v > 0; });
  }
  double non_negative(const YAML::Node& node, const std::string& field) const {
    return checked_number(node, field, "a non-negative finite number",
                          [](double v) { return v >= 0; });
  }
  // A number whose magnitude is at most `limit` (unit in the message).
  double bounded(double value, const YAML::Node& node, const std::string& field, double limit,
                 const char* unit) const {
    if (std::abs(value) > limit)
      fail(node, field,
           "expected a magnitude up to " + format_number(limit) + " " + unit + ", got " +
               describe(node));
    return value;
  }
  Eigen::Vector3d length3(const YAML::Node& node, const std::string& field) const {
    Eigen::Vector3d v = vector3(node, field);
    for (std::size_t i = 0; i < 3; ++i)
      bounded(v[static_cast<Eigen::Index>(i)], node[i], index_field(field, i), kMaxLength, "m");
    return v;
  }

  int integer_at_least(const YAML::Node& node, const std::string& field, int minimum) const {
    const std::string what = "an integer >= " + std::to_string(minimum);
    const double value = checked_number(node, field, what.c_str(), [minimum](double v) {
      return v == std::floor(v) && v >= minimum && v <= static_cast<double>(INT_MAX);
    });
    return static_cast<int>(value);
  }

  bool boolean(const YAML::Node& node, const std::string& field) const {
    if (node.IsScalar()) {
      const std::string& t = node.Scalar();
      if (t == "true") return true;
      if (t == "false") return false;
    }
    fail(node, field, "expected true or false, got " + describe(node));
  }

  // --- vectors and matrices ------------------------------------------------

  Eigen::Vector3d vector3(const YAML::Node& node, const std::string& field) const {
    if (!node.IsSequence() || node.size() != 3) {
      fail(node, field, "expected a list of 3 numbers, got " + describe(node));
    }
    Eigen::Vector3d v;
    for (std::size_t i = 0; i < 3; ++i) {
      v[static_cast<Eigen::Index>(i)] = number(node[i], index_field(field, i));
    }
    return v;
  }

  // A direction: any non-zero vector, returned normalized.
  Eigen::Vector3d axis(const YAML::Node& node, const std::string& field) const {
    const Eigen::Vector3d v = vector3(node, field);
    const double norm = v.norm();
    if (!(norm > 1e-12) || !std::isfinite(norm)) {
      fail(node, field, "expected a non-zero axis, got " + format_vector(v));
    }
    return v / norm;
  }

  // Diagonal [Ixx, Iyy, Izz] or a full 3x3 nested list; symmetric and
  // positive semidefinite.
  Eigen::Matrix3d inertia(const YAML::Node& node, const std::string& field) const {
    const std::string expected =
        "expected a list of 3 non-negative numbers (the diagonal) or a 3x3 nested list";
    if (!node.IsSequence() || node.size() != 3) {
      fail(node, field, expected + ", got " + describe(node));
    }
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
    if (!node[0].IsSequence()) {
      for (std::size_t i = 0; i < 3; ++i) {
        const auto k = static_cast<Eigen::Index>(i);
        inertia(k, k) = bounded(non_negative(node[i], index_field(field, i)), node[i],
                                index_field(field, i), kMaxMass, "kg m^2");
      }
      return inertia;
    }
    for (std::size_t i = 0; i < 3; ++i) {
      const YAML::Node row = node[i];
      const std::string row_field = index_field(field, i);
      if (!row.IsSequence() || row.size() != 3) {
        fail(row, row_field, "expected a row of 3 numbers, got " + describe(row));
      }
      for (std::size_t j = 0; j < 3; ++j) {
        inertia(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
            bounded(number(row[j], index_field(row_field, j)), row[j], index_field(row_field, j),
                    kMaxMass, "kg m^2");
      }
    }
    const double scale = std::max(1.0, inertia.cwiseAbs().maxCoeff());
    for (Eigen::Index i = 0; i < 3; ++i) {
      for (Eigen::Index j = i + 1; j < 3; ++j) {
        if (std::abs(inertia(i, j) - inertia(j, i)) > 1e-9 * scale) {
          fail(node, field,
               "expected a symmetric matrix, but [" + std::to_string(i) + "][" + std::to_string(j) +
                   "] = " + format_number(inertia(i, j)) + " differs from [" + std::to_string(j) +
                   "][" + std::to_string(i) + "] = " + format_number(inertia(j, i)));
        }
      }
    }
    inertia = 0.5 * (inertia + inertia.transpose()).eval();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(inertia, Eigen::EigenvaluesOnly);
    const Eigen::Vector3d& eigenvalues = solver.eigenvalues();
    if (eigenvalues.minCoeff() < -1e-10 * scale) {
      fail(
          node, field,
          "expected a positive semidefinite matrix, got eigenvalues " + format_vector(eigenvalues));
    }
    return inertia;
  }

  // --- shared pieces -------------------------------------------------------

  // {body: NAME, at: [x, y, z]}; the body index is into Model::bodies.
  PointSpec point(const YAML::Node& node, const std::string& field) const {
    const MapView map(*this, node, field, {"body", "at"});
    PointSpec spec;
    spec.mark = mark(node);
    const YAML::Node body_node = map.require("body");
    spec.point.body = body_index(body_node, map.field("body"));
    if (auto at = map.get("at")) spec.point.p_B = length3(*at, map.field("at"));
    return spec;
  }

  int body_index(const YAML::Node& node, const std::string& field) const {
    const std::string body = name(node, field);
    if (body == kGroundName) return kGround;
    const auto it = body_topo_index_.find(body);
    if (it == body_topo_index_.end()) fail(node, field, unknown_body_message(body));
    return it->second;
  }

  std::string unknown_body_message(const std::string& body) const {
    std::vector<std::string> known = {kGroundName};
    known.insert(known.end(), body_file_names_.begin(), body_file_names_.end());
    return "unknown body '" + body + "' (expected one of: " + join(known) + ")";
  }

  // A component option: number, string, a flat list of numbers (one row) or
  // a list of equal-length lists of numbers (a table).
  OptionValue option(const YAML::Node& node, const std::string& field) const {
    static const std::string expected =
        "expected a number, a string, a list of numbers or a list of equal-length lists of "
        "numbers";
    OptionValue value;
    value.mark = mark(node);
    if (node.IsScalar()) {
      value.text = node.Scalar();
      if (const auto number = scalar_number(node)) {
        if (!std::isfinite(*number)) {
          fail(node, field, "expected a finite number, got " + describe(node));
        }
        value.kind = OptionValue::Kind::number;
        value.number = *number;
      } else {
        value.kind = OptionValue::Kind::string;
      }
      return value;
    }
    if (!node.IsSequence() || node.size() == 0) {
      fail(node, field, expected + ", got " + describe(node));
    }
    value.kind = OptionValue::Kind::table;
    if (!node[0].IsSequence()) {
      value.rows = 1;
      value.columns = static_cast<int>(node.size());
      for (std::size_t i = 0; i < node.size(); ++i) {
        value.table.push_back(number(node[i], index_field(field, i)));
      }
      return value;
    }
    value.rows = static_cast<int>(node.size());
    value.columns = static_cast<int>(node[0].size());
    for (std::size_t i = 0; i < node.size(); ++i) {
      const YAML::Node row = node[i];
      const std::string row_field = index_field(field, i);
      if (!row.IsSequence() || row.size() == 0) {
        fail(row, row_field,
             "expected a non-empty list of numbers (a table row), got " + describe(row));
      }
      if (static_cast<int>(row.size()) != value.columns) {
        fail(row, row_field,
             "expected " + std::to_string(value.columns) +
                 " numbers like the first row (all rows of a table have the same length), got " +
                 describe(row));
      }
      for (std::size_t j = 0; j < row.size(); ++j) {
        value.table.push_back(number(row[j], index_field(row_field, j)));
      }
    }
    return value;
  }

  // --- the file ------------------------------------------------------------

  ModelFile parse(const YAML::Node& root, const std::string& base_dir) {
    if (!root.IsMap()) {
      fail(root, "",
           "expected a mapping with the model (units, bodies, ...), got " + describe(root));
    }
    const MapView top(*this, root, "",
                      {"units", "name", "gravity", "plugin_paths", "bodies", "cut_joints",
                       "subsystems", "formulation", "integrator", "compare", "solver", "planar",
                       "assembly", "nodes", "equilibrium"});
    ModelFile file;
    file.path = file_;

    parse_units(top);

    if (auto name_node = top.get("name")) {
      file.model.name = name(*name_node, "name");
    } else {
      file.model.name = fs::path(file_).stem().string();
    }
    if (auto gravity = top.get("gravity")) file.model.gravity = vector3(*gravity, "gravity");
    if (auto paths = top.get("plugin_paths")) file.plugin_paths = plugin_paths(*paths, base_dir);

    parse_bodies(top.require("bodies", "a list of bodies (may be empty: bodies: [])"), file);

    if (auto planar_node = top.get("planar")) {
      file.model.planar = boolean(*planar_node, "planar");
      if (file.model.planar) check_planar(file);
    }
    if (auto cuts = top.get("cut_joints")) file.model.cut_joints = cut_joints(*cuts);
    if (auto assembly_node = top.get("assembly")) parse_assembly(*assembly_node, file);
    std::map<std::string, SourceMark> columns;
    if (auto subsystems_node = top.get("subsystems"))
      file.subsystems = subsystems(*subsystems_node, columns);
    if (auto nodes_node = top.get("nodes")) parse_nodes(*nodes_node, file, columns);
    if (auto equilibrium_node = top.get("equilibrium")) parse_equilibrium(*equilibrium_node, file);

    file.formulation.mark = mark(root);
    if (auto formulation_node = top.get("formulation")) {
      file.formulation = component_choice(*formulation_node, "formulation", "open-loop");
    }
    file.integrator.mark = mark(root);
    if (auto integrator_node = top.get("integrator")) {
      file.integrator = component_choice(*integrator_node, "integrator", "trapezoidal");
    }
    if (auto compare_node = top.get("compare")) parse_compare(*compare_node, file);
    file.solver.mark = mark(root);
    if (auto solver_node = top.get("solver")) file.solver = solver(*solver_node);
    return file;
  }

 private:
  void parse_units(const MapView& top) {
    const std::string hint =
        "write units: {length: m, mass: kg, time: s, angle: rad} (or angle: deg)";
    const YAML::Node node = top.require("units", hint);
    const MapView units(*this, node, "units", {"length", "mass", "time", "angle"});
    const auto require_unit = [&](const std::string& key, const std::string& si) {
      const YAML::Node value = units.require(key, hint);
      const std::string text = string(value, units.field(key));
      if (text != si) {
        fail(value, units.field(key),
             "expected '" + si +
                 "' (only SI units are supported; only angles may be 'deg'), got '" + text + "'");
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

  std::vector<std::string> plugin_paths(const YAML::Node& node, const std::string& base_dir) const {
    if (!node.IsSequence()) {
      fail(node, "plugin_paths", "expected a list of folders, got " + describe(node));
    }
    std::vector<std::string> paths;
    std::error_code ec;
    fs::path base = fs::absolute(fs::path(base_dir.empty() ? "." : base_dir), ec);
    if (ec) base = fs::path(base_dir);
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string field = index_field("plugin_paths", i);
      const std::string text = string(node[i], field);
      if (text.empty()) fail(node[i], field, "expected a non-empty folder path");
      fs::path path(text);
      if (path.is_relative()) path = base / path;
      paths.push_back(path.lexically_normal().string());
    }
    return paths;
  }

  // Bodies in file order, then resolved parents, then a stable topological
  // sort (the lowest file position among the bodies whose parent is placed
  // goes next, so a file already in tree order keeps its order).
  void parse_bodies(const YAML::Node& node, ModelFile& file) {
    if (!node.IsSequence())
      fail(node, "bodies", "expected a list of bodies, got " + describe(node));
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
      body_topo_index_[b.body.name] = topo_of[static_cast<std::size_t>(i)];
      body_topo_names_.push_back(b.body.name);
    }
  }

  // Every unplaced body's parent is unplaced too, so following parents from
  // one of them must come back round; name the bodies on that loop.
  [[noreturn]] void report_cycle(const std::vector<RawBody>& raw, const std::vector<int>& parent,
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

  RawBody body(const YAML::Node& node, const std::string& field, std::size_t index) const {
    const MapView map(
        *this, node, field,
        {"name", "parent", "joint", "orientation", "mass", "shape", "com", "inertia", "z0", "zd0"});
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
    b.mass = bounded(positive(mass_node, map.field("mass")), mass_node, map.field("mass"), kMaxMass,
                     "kg");

    std::optional<Eigen::Vector3d> shape_com;
    std::optional<Eigen::Matrix3d> shape_inertia;
    if (auto shape_node = map.get("shape")) {
      const MapView shape(*this, *shape_node, map.field("shape"), {"type", "length"});
      const YAML::Node shape_type = shape.require("type", "beam or cuboid");
      const std::string kind = string(shape_type, shape.field("type"));
      if (kind != "beam" && kind != "cuboid") {
        fail(shape_type, shape.field("type"),
             "unknown shape type '" + kind + "' (expected one of: beam, cuboid)");
      }
      const YAML::Node length_node = shape.require("length");
      const double length = bounded(positive(length_node, shape.field("length")), length_node,
                                    shape.field("length"), kMaxLength, "m");
      const double ml2 = b.mass * length * length;
      if (kind == "beam") {
        shape_com = Eigen::Vector3d(0.5 * length, 0.0, 0.0);
        shape_inertia = Eigen::Vector3d(0.0, ml2 / 12.0, ml2 / 12.0).asDiagonal();
      } else {
        shape_com = Eigen::Vector3d::Zero();
        shape_inertia = Eigen::Matrix3d::Identity() * (ml2 / 6.0);
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

    const double coordinate_scale = b.joint == JointType::revolute ? angle_scale_ : 1.0;
    if (auto z0 = map.get("z0")) {
      b.z0 = number(*z0, map.field("z0")) * coordinate_scale;
      if (b.joint == JointType::prismatic) bounded(b.z0, *z0, map.field("z0"), kMaxLength, "m");
    }
    if (auto zd0 = map.get("zd0")) b.zd0 = number(*zd0, map.field("zd0")) * coordinate_scale;
    return raw;
  }

  // Planar: every revolute axis along Z, every prismatic axis in the plane,
  // every fixed orientation a rotation about Z.
  void check_planar(const ModelFile& file) {
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

  void parse_assembly(const YAML::Node& node, ModelFile& file) const {
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

  std::vector<CutJoint> cut_joints(const YAML::Node& node) const {
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
        fail(map.require("b"), map.field("b.body"),
             "a cut joint must connect two different bodies (a and b are both on '" +
                 (joint.a.body == kGround
                      ? std::string(kGroundName)
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

  // A result column name: no commas, quotes or spaces, unique in the file.
  std::string column_name(const YAML::Node& node, const std::string& field,
                          std::map<std::string, SourceMark>& columns) const {
    std::string column = name(node, field);
    if (column.find_first_of(", \t\"\r\n") != std::string::npos) {
      fail(node, field,
           "expected a column name without commas, quotes or spaces, got '" + column + "'");
    }
    for (const char* fixed : kFixedColumns)
      if (column == fixed)
        fail(node, field, "'" + column + "' is a column every run writes; pick another name");
    for (std::size_t i = 0; i < body_file_names_.size(); ++i)
      if (column == "z" + std::to_string(i + 1))
        fail(node, field,
             "'" + column + "' is the coordinate column of body '" + body_file_names_[i] +
                 "'; pick another name");
    check_unique(columns, column, node, field, "result column");
    return column;
  }

  // nodes: {NODE: COLUMN | null}. Every node must be some port's.
  void parse_nodes(const YAML::Node& node, ModelFile& file,
                   std::map<std::string, SourceMark>& columns) const {
    const MapView map(*this, node, "nodes", {});
    file.nodes_mark = mark(node);
    for (const Entry& e : map.entries()) {
      bool used = false;
      for (const auto& spec : file.subsystems)
        for (const auto& [key, port] : spec.ports) used = used || port.node == e.key;
      if (!used)
        fail(e.value, map.field(e.key),
             "unknown node '" + e.key + "' (no subsystem port names it under ports)");
      file.node_columns[e.key] =
          e.value.IsNull() ? "" : column_name(e.value, map.field(e.key), columns);
    }
  }

  // equilibrium: {free: [state, ...]}
  void parse_equilibrium(const YAML::Node& node, ModelFile& file) const {
    const MapView map(*this, node, "equilibrium", {"free"});
    const YAML::Node free = map.require("free", "a list of states to solve for at t = 0");
    if (!free.IsSequence() || free.size() == 0)
      fail(free, "equilibrium.free",
           "expected a non-empty list of state names (result columns), got " + describe(free));
    for (std::size_t i = 0; i < free.size(); ++i) {
      file.equilibrium_free.push_back(name(free[i], index_field("equilibrium.free", i)));
      file.equilibrium_marks.push_back(mark(free[i]));
    }
  }

  std::vector<SubsystemSpec> subsystems(const YAML::Node& node,
                                        std::map<std::string, SourceMark>& columns) const {
    if (!node.IsSequence()) {
      fail(node, "subsystems", "expected a list of subsystems, got " + describe(node));
    }
    std::vector<SubsystemSpec> specs;
    std::map<std::string, SourceMark> names;
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string field = index_field("subsystems", i);
      const MapView map(*this, node[i], field, {});
      SubsystemSpec spec;
      spec.mark = mark(node[i]);
      const YAML::Node name_node = map.require("name");
      spec.name = name(name_node, map.field("name"));
      check_unique(names, spec.name, name_node, map.field("name"), "subsystem");
      spec.type =
          name(map.require("type", "the component id, e.g. spring-damper"), map.field("type"));
      for (const Entry& entry : map.entries()) {
        const std::string entry_field = map.field(entry.key);
        if (entry.key == "name" || entry.key == "type") continue;
        if (entry.key == "points") {
          const MapView points(*this, entry.value, entry_field, {});
          for (const Entry& p : points.entries()) {
            spec.points[p.key] = point(p.value, points.field(p.key));
          }
        } else if (entry.key == "ports") {
          // ports: {KEY: NODE}: ports naming the same node are joined.
          const MapView ports(*this, entry.value, entry_field, {});
          for (const Entry& p : ports.entries()) {
            if (!p.value.IsScalar())
              fail(p.value, ports.field(p.key),
                   "expected one node name (a port joins exactly one node), got " +
                       describe(p.value));
            spec.ports[p.key] = PortSpec{name(p.value, ports.field(p.key)), mark(p.value)};
          }
        } else if (entry.key == "states" || entry.key == "outputs") {
          // Column names of the instance's states and outputs; null hides one.
          const bool states_key = entry.key == "states";
          auto& target = states_key ? spec.state_names : spec.output_names;
          const MapView cols(*this, entry.value, entry_field, {});
          for (const Entry& s : cols.entries()) {
            const std::string column_field = cols.field(s.key);
            spec.column_marks[entry.key + "." + s.key] = mark(s.key_node);
            if (s.value.IsNull()) {
              target[s.key] = "";
              continue;
            }
            target[s.key] = column_name(s.value, column_field, columns);
          }
        } else {
          spec.options[entry.key] = option(entry.value, entry_field);
        }
      }
      specs.push_back(std::move(spec));
    }
    return specs;
  }

  // `formulation:` and `integrator:` alike: a component id, or {name: ID, options...}.
  ComponentChoice component_choice(const YAML::Node& node, const std::string& section,
                                   const std::string& example) const {
    ComponentChoice spec;
    spec.mark = mark(node);
    if (node.IsScalar()) {
      spec.name = name(node, section);
      return spec;
    }
    if (!node.IsMap()) {
      fail(node, section,
           "expected " + std::string(section == "integrator" ? "an " : "a ") + section +
               " name or a mapping {name: ..., options...}, got " + describe(node));
    }
    const MapView map(*this, node, section, {});
    spec.name =
        name(map.require("name", "the " + section + " id, e.g. " + example), map.field("name"));
    for (const Entry& entry : map.entries()) {
      if (entry.key == "name") continue;
      spec.options[entry.key] = option(entry.value, map.field(entry.key));
    }
    return spec;
  }

  // compare: {formulations: [A, B], integrators: [C]}: what `monohydra compare`
  // runs on this model when the command line names nothing.
  void parse_compare(const YAML::Node& node, ModelFile& file) const {
    const MapView map(*this, node, "compare", {"formulations", "integrators"});
    const auto names = [&](const char* key, std::vector<std::string>& out) {
      auto list = map.get(key);
      if (!list) return;
      const std::string field = map.field(key);
      if (!list->IsSequence() || list->size() == 0)
        fail(*list, field, "expected a non-empty list of component ids, got " + describe(*list));
      for (size_t i = 0; i < list->size(); ++i)
        out.push_back(name((*list)[i], field + "[" + std::to_string(i) + "]"));
    };
    names("formulations", file.compare_formulations);
    names("integrators", file.compare_integrators);
  }

  SolverSettings solver(const YAML::Node& node) const {
    const MapView map(*this, node, "solver", {"dt", "t_end", "max_iterations", "tol_position"});
    SolverSettings settings;
    settings.mark = mark(node);
    if (auto dt = map.get("dt")) {
      settings.dt = positive(*dt, "solver.dt");
      settings.dt_mark = mark(*dt);
    }
    if (auto t_end = map.get("t_end")) {
      settings.t_end = non_negative(*t_end, "solver.t_end");
      settings.t_end_mark = mark(*t_end);
    }
    if (auto iterations = map.get("max_iterations")) {
      settings.max_iterations = integer_at_least(*iterations, "solver.max_iterations", 1);
    }
    if (auto tol = map.get("tol_position")) {
      settings.tol_position = positive(*tol, "solver.tol_position");
    }
    return settings;
  }

  void check_unique(std::map<std::string, SourceMark>& seen, const std::string& value,
                    const YAML::Node& node, const std::string& field, const char* what) const {
    const auto [it, inserted] = seen.emplace(value, mark(node));
    if (!inserted) {
      fail(node, field,
           std::string("duplicate ") + what + " name '" + value + "' (first defined at " +
               location(it->second) + ")");
    }
  }

  static std::string location(const SourceMark& m) {
    return "line " + std::to_string(m.line) + ", column " + std::to_string(m.column);
  }

  std::string file_;
  mutable std::vector<std::pair<YAML::Node, YAML::Mark>> null_value_marks_;
  double angle_scale_ = 1.0;
  bool planar_ = false;
  std::vector<std::string> body_file_names_;    // bodies in file order
  std::vector<std::string> body_topo_names_;    // bodies in Model::bodies order
  std::map<std::string, int> body_topo_index_;  // name -> index into Model::bodies
};

MapView::MapView(const Parser& parser, const YAML::Node& node, std::string field,
                 const std::vector<std::string>& allowed)
    : parser_(parser), node_(node), field_(std::move(field)) {
  if (!node.IsMap()) {
    parser_.fail(node, field_, "expected a mapping, got " + describe(node));
  }
  for (auto it = node.begin(); it != node.end(); ++it) {
    const YAML::Node key = it->first;
    if (!key.IsScalar()) {
      parser_.fail(key, field_, "expected a plain key, got " + describe(key));
    }
    const std::string& name = key.Scalar();
    const std::string key_field = child_field(field_, name);
    if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), name) == allowed.end()) {
      parser_.fail(key, key_field,
                   "unknown key '" + name + "' (expected one of: " + join(allowed) + ")");
    }
    if (find(name) != nullptr) {
      const SourceMark first = parser_.mark(find(name)->key_node);
      parser_.fail(key, key_field,
                   "duplicate key '" + name + "' (first written at line " +
                       std::to_string(first.line) + ")");
    }
    if (it->second.IsNull()) parser_.mark_null_value(it->second, key);
    entries_.push_back(Entry{name, key, it->second});
  }
}

YAML::Node MapView::require(const std::string& key, const std::string& hint) const {
  if (const Entry* entry = find(key)) return entry->value;
  parser_.fail(node_, child_field(field_, key),
               "missing required key '" + key + "'" + (hint.empty() ? "" : " (" + hint + ")"));
}

}  // namespace

namespace {
// Where a document's first content is, if it has any. yaml-cpp 0.7's LoadAll
// never returns on a stray top-level ',' (its parser yields empty documents
// forever without consuming it; found by tests/fuzz), so documents are read
// one at a time and only the first two are looked at.
class FirstContent : public YAML::EventHandler {
 public:
  std::optional<YAML::Mark> mark;
  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark& m, YAML::anchor_t) override { see(m); }
  void OnScalar(const YAML::Mark& m, const std::string&, YAML::anchor_t,
                const std::string&) override {
    see(m);
  }
  void OnSequenceStart(const YAML::Mark& m, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {
    see(m);
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& m, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {
    see(m);
  }
  void OnMapEnd() override {}

 private:
  void see(const YAML::Mark& m) {
    if (!mark) mark = m;
  }
};

SourceMark source_mark(const std::string& file, const YAML::Mark& m) {
  SourceMark mark;
  mark.file = file;
  if (!m.is_null() && m.line >= 0) {
    mark.line = m.line + 1;
    mark.column = m.column >= 0 ? m.column + 1 : 0;
  }
  return mark;
}
}  // namespace

ModelFile parse_model_text(const std::string& yaml_text, const std::string& file_label,
                           const std::string& base_dir) {
  YAML::Node root;
  try {
    std::istringstream in(yaml_text);
    YAML::Parser reader(in);
    FirstContent first, second;
    if (reader.HandleNextDocument(first) && reader.HandleNextDocument(second) && second.mark)
      throw InputError(source_mark(file_label, *second.mark), "",
                       "expected a single YAML document, found more than one");
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError(source_mark(file_label, e.mark), "", "malformed YAML: " + e.msg);
  }
  Parser parser(file_label);
  return parser.parse(root, base_dir);
}

// A model file is a regular text file of at most 64 MiB that ends with a line
// break: /dev/zero, a FIFO or a binary are refused before yaml-cpp reads them
// (it would grow without bound), and a file cut mid-line is caught.
ModelFile load_model_file(const std::string& path) {
  SourceMark mark;
  mark.file = path;
  std::error_code ec;
  const fs::path file(path);
  if (!fs::exists(file, ec)) throw InputError(mark, "", "cannot open the model file: no such file");
  if (fs::is_directory(file, ec)) {
    throw InputError(mark, "", "cannot open the model file: it is a folder");
  }
  if (!fs::is_regular_file(file, ec)) {
    throw InputError(mark, "",
                     "cannot read the model file: not a regular file (a device, FIFO or socket)");
  }
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec || size > kMaxFileBytes) {
    throw InputError(mark, "",
                     "the model file is " + std::to_string(size) +
                         " bytes, above the limit of 67108864 bytes (64 MiB)");
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    throw InputError(mark, "", std::string("cannot open the model file: ") + std::strerror(errno));
  }
  // One byte more than its size, to notice a file that grows while read.
  std::string text(static_cast<std::size_t>(size) + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw InputError(mark, "", "cannot read the model file");
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > size) throw InputError(mark, "", "the model file changed while being read");
  if (const auto nul = text.find('\0'); nul != std::string::npos)
    throw InputError(mark, "",
                     "not a text file: it holds a NUL byte at offset " + std::to_string(nul));
  if (!text.empty() && text.back() != '\n') {
    mark.line = static_cast<int>(std::count(text.begin(), text.end(), '\n')) + 1;
    throw InputError(mark, "",
                     "the file does not end with a line break, so it may have been cut short "
                     "(end its last line with one)");
  }
  fs::path base = file.parent_path();
  if (base.empty()) base = ".";
  return parse_model_text(text, path, base.string());
}

}  // namespace mh
