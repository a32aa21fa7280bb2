// Mappings of a model file: every key plain and written once, and, where the
// section lists its keys, none other (typo protection).
#include <algorithm>
#include <string>
#include <utility>

#include "parser.hpp"

namespace mh::model_file_detail {

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

}  // namespace mh::model_file_detail
