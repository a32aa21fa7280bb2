// Networks in the model file: a subsystem's ports name nodes (ports/<key>:
// NODE), and every port naming a node shares the node's effort state (a
// hydraulic node's pressure). The node's row is its balance: each port adds
// what leaves the node through it. A node is created by the first port that
// names it, so instances may be listed in any order.
#include <cmath>
#include <limits>

#include "engine.hpp"

namespace mh {
namespace {

std::string who(const SubsystemInstance& s) {
  return "subsystem '" + s.spec->name + "' (" + s.spec->type + ")";
}

std::string port_name(const Simulation::Engine& e, const NodePort& p) {
  return "subsystem '" + e.subsystems[static_cast<size_t>(p.subsystem)].spec->name + "' port '" +
         p.key + "'";
}

std::string port_list(const SubsystemSpec& spec) {
  std::string out;
  for (const auto& [key, port] : spec.ports) out += (out.empty() ? "" : ", ") + key;
  return out.empty() ? "none" : out;
}

}  // namespace

mh_status Simulation::Engine::add_port(InstanceHost& h, const mh_port_spec& spec, int32_t* index) {
  SubsystemInstance& s = subsystems[static_cast<size_t>(h.subsystem)];
  const std::string key = spec.key != nullptr ? spec.key : "";
  const auto fail_input = [&](const SourceMark& mark, const std::string& field,
                              const std::string& expected) {
    const InputError err(mark, field, expected);
    reports.last_plugin_error = err.what();
    if (!reports.option_error) reports.option_error = std::make_unique<InputError>(err);
    if (reports.log) reports.log(MH_LOG_ERROR, h.source, err.what());
    return MH_ERROR;
  };
  if (key.empty() || (spec.role != MH_PORT_FLOW && spec.role != MH_PORT_EFFORT)) {
    reports.last_plugin_error = h.source + ": add_port: expected a port name and a role";
    return MH_ERROR;
  }
  // A port of the component that the model leaves unconnected.
  auto it = s.spec->ports.find(key);
  if (it == s.spec->ports.end())
    return fail_input(s.spec->mark, who(s) + " port '" + key + "'",
                      "the port is not connected: name its node under ports (e.g. ports: {" + key +
                          ": NODE}); connected here: " + port_list(*s.spec));
  const std::string& node_name = it->second.node;
  const SourceMark& mark = it->second.mark;
  Node* node = nullptr;
  for (auto& nd : states.nodes)
    if (nd.name == node_name) node = &nd;
  const std::string domain = spec.domain != nullptr ? spec.domain : "";
  const std::string unit = spec.unit != nullptr ? spec.unit : "";
  if (node == nullptr) {
    for (const auto& v : states.state_info)
      if (v.qualified == node_name)
        return fail_input(mark, who(s) + " port '" + key + "'",
                          "a node name that is not also a state's name, got '" + node_name + "'");
    Node fresh;
    fresh.name = node_name;
    fresh.domain = domain;
    fresh.unit = unit;
    fresh.mark = mark;
    auto named = file->node_columns.find(node_name);
    VariableInfo info;
    info.name = named != file->node_columns.end() ? named->second : node_name;
    info.qualified = node_name;
    info.unit = unit;
    fresh.state = add_state_record(info, 0.0, std::numeric_limits<double>::infinity());
    states.nodes.push_back(fresh);
    node = &states.nodes.back();
  } else if (node->domain != domain) {
    return fail_input(mark, who(s) + " port '" + key + "'",
                      "a " + node->domain + " port on node '" + node_name + "' (it joins " +
                          port_name(*this, node->ports.front()) + "), got a " + domain + " port");
  }
  if (spec.role == MH_PORT_EFFORT)
    for (const auto& p : node->ports)
      if (p.role == MH_PORT_EFFORT)
        return fail_input(mark, who(s) + " port '" + key + "'",
                          "at most one port imposing the effort of node '" + node_name + "', but " +
                              port_name(*this, p) + " imposes it too (two outputs on one node)");
  const double y0 = spec.initial;
  if (std::isfinite(y0)) {
    const double have = states.y[node->state];
    if (node->has_initial && std::abs(have - y0) > 1e-12 * std::max(std::abs(have), std::abs(y0)))
      return fail_input(mark, who(s) + " port '" + key + "'",
                        "the initial " + unit + " of node '" + node_name + "' given once, got " +
                            std::to_string(y0) + " here and " + std::to_string(have) +
                            " from another port");
    states.y[node->state] = y0;
    node->has_initial = true;
  }
  if (spec.abs_tolerance > 0.0)
    states.state_tol[node->state] = std::min(states.state_tol[node->state], spec.abs_tolerance);
  node->ports.push_back(NodePort{h.subsystem, key, spec.role});
  for (int touched : s.touched)
    if (touched == node->state) {
      *index = node->state;
      return MH_OK;
    }
  s.touched.push_back(node->state);
  *index = node->state;
  return MH_OK;
}

// After every instance is set up: each port the model names is one the
// component declared, no node is a dead end, and each has a start value and a
// tolerance.
void Simulation::Engine::check_network() const {
  for (const auto& s : subsystems) {
    for (const auto& [key, port] : s.spec->ports) {
      bool declared = false;
      for (const auto& nd : states.nodes)
        for (const auto& p : nd.ports)
          declared =
              declared || (p.subsystem >= 0 &&
                           &subsystems[static_cast<size_t>(p.subsystem)] == &s && p.key == key);
      if (!declared)
        throw InputError(port.mark, who(s) + " port '" + key + "'",
                         "unknown port (this component has no port '" + key + "')");
    }
  }
  for (const auto& nd : states.nodes) {
    if (nd.ports.size() < 2)
      throw InputError(nd.mark, port_name(*this, nd.ports.front()),
                       "a port left unconnected: node '" + nd.name +
                           "' joins no other port (name it on another component's port)");
    bool free = false;
    for (const auto& f : file->equilibrium_free)
      free = free || f == nd.name || f == states.state_info[static_cast<size_t>(nd.state)].name;
    if (!nd.has_initial && !free)
      throw InputError(nd.mark, "node '" + nd.name + "'",
                       "an initial " + nd.unit +
                           ": none of its ports gives one (e.g. a volume's initial_pressure, "
                           "a pressure source), and it is not under equilibrium.free");
    for (int i = 0; i < n_s; ++i)
      if (i != nd.state && !states.state_info[static_cast<size_t>(i)].name.empty() &&
          states.state_info[static_cast<size_t>(i)].name ==
              states.state_info[static_cast<size_t>(nd.state)].name)
        throw InputError(nd.mark, "node '" + nd.name + "'",
                         "a result column of its own, but '" +
                             states.state_info[static_cast<size_t>(i)].name +
                             "' is also the column of state '" +
                             states.state_info[static_cast<size_t>(i)].qualified +
                             "' (rename one, or give the node a column under nodes)");
    if (!std::isfinite(states.state_tol[nd.state]))
      throw InputError(nd.mark, "node '" + nd.name + "'",
                       "a Newton tolerance: none of its ports gives one (connect a volume or "
                       "a source to it)");
  }
}

}  // namespace mh
