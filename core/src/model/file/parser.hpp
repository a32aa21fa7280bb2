// The model-file parser (docs/model-format.md), private to the core. One class
// reads the whole file; its members are defined by section, one file each
// (read_file.cpp, units.cpp, bodies.cpp, cut_joints.cpp, subsystems.cpp,
// choices.cpp, solver.cpp, output.cpp), on the shared readers of values.cpp and
// map_view.cpp. Every problem becomes an InputError with the file, line,
// field and expectation.
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "monohydra/core/model_file.hpp"

namespace mh::model_file_detail {

inline constexpr const char* kGroundName = "ground";
// Magnitudes beyond these are typos (a missing exponent sign, a unit slip):
// refused with the range rather than left to overflow the solver.
inline constexpr double kMaxMass = 1e12;    // kg, and kg m^2 for inertias
inline constexpr double kMaxLength = 1e6;   // m
inline constexpr double kMaxGravity = 1e4;  // m/s^2: a thousand g, beyond any machine's test rig

// Text for messages and field paths (values.cpp).
std::string join(const std::vector<std::string>& items);
std::string format_number(double value);
std::string format_vector(const Eigen::Vector3d& v);
std::string child_field(const std::string& base, const std::string& key);
std::string index_field(const std::string& base, std::size_t index);
std::string describe(const YAML::Node& node);
std::optional<double> scalar_number(const YAML::Node& node);

struct Entry {
  std::string key;
  YAML::Node key_node;
  YAML::Node value;
};

class Parser;

// A mapping whose keys have been checked: no duplicates and, when a list of
// allowed keys is given, nothing else (typo protection). map_view.cpp.
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
  BodyShape shape;
  YAML::Node name_node;
  std::string parent_name;
  YAML::Node parent_node;
  SourceMark mark;
  std::string field;
};

class Parser {
 public:
  explicit Parser(std::string file) : file_(std::move(file)) {}

  SourceMark mark(const YAML::Node& node) const;

  // yaml-cpp marks an empty value ("mass:") at the token after it, often on
  // the next line; MapView records its key's mark here instead.
  void mark_null_value(const YAML::Node& value, const YAML::Node& key) const {
    null_value_marks_.emplace_back(value, key.Mark());
  }

  [[noreturn]] void fail(const YAML::Node& node, const std::string& field,
                         const std::string& expectation) const {
    throw InputError(mark(node), field, expectation);
  }

  // --- scalars, vectors, matrices, options (values.cpp) ----------------------

  std::string string(const YAML::Node& node, const std::string& field) const;
  std::string name(const YAML::Node& node, const std::string& field) const;
  double checked_number(const YAML::Node& node, const std::string& field, const char* what,
                        const std::function<bool(double)>& ok) const;
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
  double bounded(double value, const YAML::Node& node, const std::string& field, double limit,
                 const char* unit) const;
  Eigen::Vector3d length3(const YAML::Node& node, const std::string& field) const;
  int integer_at_least(const YAML::Node& node, const std::string& field, int minimum) const;
  bool boolean(const YAML::Node& node, const std::string& field) const;
  Eigen::Vector3d vector3(const YAML::Node& node, const std::string& field) const;
  Eigen::Vector3d axis(const YAML::Node& node, const std::string& field) const;
  Eigen::Matrix3d inertia(const YAML::Node& node, const std::string& field) const;
  OptionValue option(const YAML::Node& node, const std::string& field) const;

  // --- points on bodies (bodies.cpp) -----------------------------------------

  PointSpec point(const YAML::Node& node, const std::string& field) const;
  int body_index(const YAML::Node& node, const std::string& field) const;
  std::string unknown_body_message(const std::string& body) const;

  // --- the file (read_file.cpp) ----------------------------------------------

  ModelFile parse(const YAML::Node& root, const std::string& base_dir);

 private:
  std::vector<std::string> plugin_paths(const YAML::Node& node, const std::string& base_dir) const;
  std::map<std::string, std::string> plugin_libraries(const YAML::Node& node,
                                                      const std::string& base_dir) const;

  // units.cpp
  void parse_units(const MapView& top);

  // bodies.cpp
  void parse_bodies(const YAML::Node& node, ModelFile& file);
  [[noreturn]] void report_cycle(const std::vector<RawBody>& raw, const std::vector<int>& parent,
                                 const std::vector<int>& topo_of) const;
  RawBody body(const YAML::Node& node, const std::string& field, std::size_t index) const;
  void add_payload(const YAML::Node& node, const std::string& field, Body& b) const;
  void check_planar(const ModelFile& file);

  // cut_joints.cpp
  void parse_assembly(const YAML::Node& node, ModelFile& file) const;
  std::vector<CutJoint> cut_joints(const YAML::Node& node) const;

  // subsystems.cpp
  std::string column_name(const YAML::Node& node, const std::string& field,
                          std::map<std::string, SourceMark>& columns) const;
  void parse_nodes(const YAML::Node& node, ModelFile& file,
                   std::map<std::string, SourceMark>& columns) const;
  std::string reserved_column(const std::string& column) const;
  void check_node_columns(const ModelFile& file) const;
  void parse_equilibrium(const YAML::Node& node, ModelFile& file) const;
  std::vector<SubsystemSpec> subsystems(const YAML::Node& node,
                                        std::map<std::string, SourceMark>& columns) const;

  // choices.cpp
  ComponentChoice component_choice(const YAML::Node& node, const std::string& section,
                                   const std::string& example) const;
  void parse_compare(const YAML::Node& node, ModelFile& file) const;

  // solver.cpp
  SolverSettings solver(const YAML::Node& node) const;

  // output.cpp
  OutputSettings output(const YAML::Node& node) const;
  // inputs.cpp
  std::vector<InputSpec> inputs(const YAML::Node& node) const;
  // sensors.cpp
  std::vector<SensorSpec> sensors(const YAML::Node& node) const;

  // values.cpp
  void check_unique(std::map<std::string, SourceMark>& seen, const std::string& value,
                    const YAML::Node& node, const std::string& field, const char* what) const;
  static std::string location(const SourceMark& m);

  std::string file_;
  mutable std::vector<std::pair<YAML::Node, YAML::Mark>> null_value_marks_;
  double angle_scale_ = 1.0;
  bool planar_ = false;
  std::vector<std::string> body_file_names_;  // bodies in file order
  // Each node a port names: its first port's YAML node and field.
  mutable std::map<std::string, std::pair<YAML::Node, std::string>> port_nodes_;
  std::vector<std::string> body_topo_names_;    // bodies in Model::bodies order
  std::map<std::string, int> body_topo_index_;  // name -> index into Model::bodies
};

}  // namespace mh::model_file_detail
