#include "parameter_path.hpp"

#include <algorithm>
#include <stdexcept>

#include "monohydra/core/model_file.hpp"

namespace mh::host {
namespace {

const std::vector<std::string> kSolverKeys = {"dt", "t_end", "max_iterations", "max_step_halvings",
                                              "tol_position"};

bool is_component(const std::string& key) {
  return key == "formulation" || key == "integrator";
}

// The default component when the file names none (the core's choice).
const char* default_component(const std::string& key) {
  return key == "formulation" ? kDefaultFormulation : kDefaultIntegrator;
}

std::string keys_of(const YAML::Node& map) {
  std::string out;
  for (const auto& kv : map) {
    if (!out.empty()) out += ", ";
    out += kv.first.as<std::string>("?");
  }
  return out.empty() ? "nothing" : out;
}

// The element of a sequence a segment names: the item whose `name` is it,
// else the index it spells; -1 when none.
long find_item(const YAML::Node& seq, const std::string& segment) {
  for (std::size_t i = 0; i < seq.size(); ++i) {
    const YAML::Node item = seq[i];
    if (item.IsMap() && item["name"] && item["name"].IsScalar() && item["name"].Scalar() == segment)
      return static_cast<long>(i);
  }
  if (!segment.empty() &&
      std::all_of(segment.begin(), segment.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    const long index = std::stol(segment);
    if (index < static_cast<long>(seq.size())) return index;
  }
  return -1;
}

std::string names_of(const YAML::Node& seq) {
  std::string out;
  for (std::size_t i = 0; i < seq.size(); ++i) {
    if (!out.empty()) out += ", ";
    const YAML::Node item = seq[i];
    out += item.IsMap() && item["name"] && item["name"].IsScalar() ? item["name"].Scalar()
                                                                   : std::to_string(i);
  }
  return out.empty() ? "nothing" : out;
}

std::string join(const std::vector<std::string>& parts, std::size_t n) {
  std::string out;
  for (std::size_t i = 0; i < n; ++i) out += (i > 0 ? "/" : "") + parts[i];
  return out;
}

// Walks `root` along `parts`; returns the reason it cannot, "" when it can.
// With `value`, sets it (creating solver and component keys the path may add).
std::string walk(YAML::Node root, const std::vector<std::string>& parts, const YAML::Node* value) {
  if (parts.empty()) return "an empty path";
  for (const auto& p : parts)
    if (p.empty()) return "an empty segment (write a/b/c)";
  if (!root.IsMap()) return "the model is not a mapping";
  const std::string& top = parts.front();
  if (top == "solver" && parts.size() == 2) {
    if (std::find(kSolverKeys.begin(), kSolverKeys.end(), parts[1]) == kSolverKeys.end())
      return "no solver setting '" + parts[1] +
             "' (there are dt, t_end, max_iterations, max_step_halvings, tol_position)";
    if (value != nullptr) {
      if (!root["solver"] || !root["solver"].IsMap())
        root["solver"] = YAML::Node(YAML::NodeType::Map);
      YAML::Node solver = root["solver"];
      solver[parts[1]] = YAML::Clone(*value);
    }
    return "";
  }
  if (is_component(top) && parts.size() == 2) {
    if (value != nullptr) {
      YAML::Node existing = root[top];
      YAML::Node map(YAML::NodeType::Map);
      if (existing && existing.IsScalar()) {
        map["name"] = existing.Scalar();
      } else if (existing && existing.IsMap()) {
        map.reset(existing);
      } else {
        map["name"] = default_component(top);
      }
      map[parts[1]] = YAML::Clone(*value);
      root[top] = map;
    }
    return "";
  }
  YAML::Node node = root;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const std::string& seg = parts[i];
    YAML::Node child;  // reset(), not =: assigning a Node writes through to the tree
    if (node.IsMap()) {
      if (!node[seg])
        return "no '" + seg + "' in " + (i == 0 ? std::string("the model") : join(parts, i)) +
               " (it has " + keys_of(node) + ")";
      child.reset(node[seg]);
    } else if (node.IsSequence()) {
      const long index = find_item(node, seg);
      if (index < 0)
        return "no item named '" + seg + "' in " + join(parts, i) + " (it has " + names_of(node) +
               ")";
      child.reset(node[static_cast<std::size_t>(index)]);
    } else {
      return join(parts, i) + " is a single value, it has no '" + seg + "'";
    }
    if (i + 1 == parts.size()) {
      if (value != nullptr) {
        if (node.IsMap()) {
          node[seg] = YAML::Clone(*value);
        } else {
          node[static_cast<std::size_t>(find_item(node, seg))] = YAML::Clone(*value);
        }
      }
      return "";
    }
    node.reset(child);
  }
  return "";
}

}  // namespace

std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (;;) {
    const std::size_t slash = path.find('/', start);
    parts.push_back(path.substr(start, slash - start));
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
  return parts;
}

std::string check_path(const YAML::Node& root, const std::string& path) {
  return walk(YAML::Clone(root), split_path(path), nullptr);
}

std::optional<YAML::Node> value_at(const YAML::Node& root, const std::string& path) {
  YAML::Node node;
  node.reset(root);
  for (const std::string& seg : split_path(path)) {
    YAML::Node child;
    if (node.IsMap()) {
      const YAML::Node& map = node;
      if (!map[seg]) return std::nullopt;
      child.reset(map[seg]);
    } else if (node.IsSequence()) {
      const long index = find_item(node, seg);
      if (index < 0) return std::nullopt;
      child.reset(node[static_cast<std::size_t>(index)]);
    } else {
      return std::nullopt;
    }
    node.reset(child);
  }
  return node;
}

void set_path(YAML::Node& root, const std::string& path, const YAML::Node& value) {
  const std::string reason = walk(root, split_path(path), &value);
  if (!reason.empty()) throw std::invalid_argument(path + ": " + reason);
}

}  // namespace mh::host
