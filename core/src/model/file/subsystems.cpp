// subsystems with their points, ports, options and result columns (states,
// outputs); nodes (the ports' junctions) and equilibrium (states solved at
// t = 0), which name them.
#include <map>
#include <utility>

#include "parser.hpp"

namespace mh::model_file_detail {

namespace {
// Result columns every run writes; a state, output or node may not take them.
const char* const kFixedColumns[] = {"t", "KE", "PE", "W", "drift", "phi_norm", "iters"};
}  // namespace

// A result column name: no commas, quotes or spaces, unique in the file.
std::string Parser::column_name(const YAML::Node& node, const std::string& field,
                                std::map<std::string, SourceMark>& columns) const {
  std::string column = name(node, field);
  if (column.find_first_of(", \t\"\r\n") != std::string::npos) {
    fail(node, field,
         "expected a column name without commas, quotes or spaces, got '" + column + "'");
  }
  const std::string taken = reserved_column(column);
  if (!taken.empty()) fail(node, field, "'" + column + "' is " + taken + "; pick another name");
  check_unique(columns, column, node, field, "result column");
  return column;
}

// Why `column` is a column of every run ("" when it is free).
std::string Parser::reserved_column(const std::string& column) const {
  for (const char* fixed : kFixedColumns)
    if (column == fixed) return "a column every run writes";
  for (std::size_t i = 0; i < body_file_names_.size(); ++i)
    if (column == "z" + std::to_string(i + 1))
      return "the coordinate column of body '" + body_file_names_[i] + "'";
  return "";
}

// A node that nodes: does not rename writes its pressure (or other effort)
// under its own name: a node named `t` or `z1` would write a second column of
// that name, which no reader of the CSV can tell apart.
void Parser::check_node_columns(const ModelFile& file) const {
  for (const auto& [node_name, where] : port_nodes_) {
    const auto renamed = file.node_columns.find(node_name);
    if (renamed != file.node_columns.end() && !renamed->second.empty()) continue;
    const std::string taken = reserved_column(node_name);
    if (!taken.empty())
      fail(where.first, where.second,
           "a node name that is not a result column every run has, got '" + node_name + "' (" +
               taken + "); rename the node, or give it a column under nodes: {" + node_name +
               ": NAME}");
  }
}

// nodes: {NODE: COLUMN | null}. Every node must be some port's.
void Parser::parse_nodes(const YAML::Node& node, ModelFile& file,
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
void Parser::parse_equilibrium(const YAML::Node& node, ModelFile& file) const {
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

std::vector<SubsystemSpec> Parser::subsystems(const YAML::Node& node,
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
            fail(
                p.value, ports.field(p.key),
                "expected one node name (a port joins exactly one node), got " + describe(p.value));
          spec.ports[p.key] = PortSpec{name(p.value, ports.field(p.key)), mark(p.value)};
          port_nodes_.emplace(spec.ports[p.key].node, std::make_pair(p.value, ports.field(p.key)));
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

}  // namespace mh::model_file_detail
