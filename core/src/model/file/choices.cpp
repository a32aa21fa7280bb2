// formulation, integrator and compare: which components run the model, and
// which `monohydra compare` runs when the command line names none.
#include "parser.hpp"

namespace mh::model_file_detail {

// `formulation:` and `integrator:` alike: a component id, or {name: ID, options...}.
ComponentChoice Parser::component_choice(const YAML::Node& node, const std::string& section,
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
void Parser::parse_compare(const YAML::Node& node, ModelFile& file) const {
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

}  // namespace mh::model_file_detail
