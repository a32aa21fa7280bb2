#include "model_description_rules.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <set>

namespace mh::test {

namespace {

using Rules = std::vector<std::string>;

bool is_c_identifier(const std::string& s) {
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s.front())) != 0) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

// Attributes outside `allowed` (the schema's for that element).
void only_attributes(const pugi::xml_node& n, const std::set<std::string>& allowed, Rules& out) {
  for (const pugi::xml_attribute a : n.attributes())
    if (allowed.count(a.name()) == 0)
      out.push_back(std::string("<") + n.name() + "> has the attribute " + a.name() +
                    ", which the schema does not define");
}

void required(const pugi::xml_node& n, const std::vector<std::string>& names, Rules& out) {
  for (const std::string& a : names)
    if (!n.attribute(a.c_str()))
      out.push_back(std::string("<") + n.name() + "> lacks the required attribute " + a);
}

// The children in the schema's order, each at most once unless `repeated`.
void element_order(const pugi::xml_node& root, const std::vector<std::string>& order, Rules& out) {
  std::size_t at = 0;
  std::set<std::string> seen;
  for (const pugi::xml_node c : root.children()) {
    if (c.type() != pugi::node_element) continue;
    const auto it = std::find(order.begin(), order.end(), c.name());
    if (it == order.end()) {
      out.push_back(std::string("<") + c.name() + "> is not an element of <" + root.name() + ">");
      continue;
    }
    const auto k = static_cast<std::size_t>(it - order.begin());
    if (k < at || seen.count(c.name()) > 0)
      out.push_back(std::string("<") + c.name() + "> is out of the schema's order or repeated");
    at = k;
    seen.insert(c.name());
  }
}

// Causality x variability (FMI 3.0 Table 18; FMI 2.0 section 2.2.7).
bool allowed_combination(const std::string& causality, const std::string& variability) {
  static const std::map<std::string, std::set<std::string>> by_variability = {
      {"constant", {"output", "local"}},
      {"fixed", {"parameter", "calculatedParameter", "local", "structuralParameter"}},
      {"tunable", {"parameter", "calculatedParameter", "local", "structuralParameter"}},
      {"discrete", {"input", "output", "local"}},
      {"continuous", {"input", "output", "local", "independent"}}};
  const auto it = by_variability.find(variability);
  return it != by_variability.end() && it->second.count(causality) > 0;
}

// The initial values allowed for a causality (FMI 3.0 Table 19; FMI 2.0 p. 50),
// "" meaning the attribute is absent; the first is the default.
std::vector<std::string> allowed_initial(const std::string& causality,
                                         const std::string& variability) {
  if (causality == "parameter" || causality == "structuralParameter") return {"exact"};
  if (causality == "calculatedParameter") return {"calculated", "approx"};
  if (causality == "input" || causality == "independent") return {""};
  if (causality == "output")
    return variability == "constant" ? std::vector<std::string>{"exact"}
                                     : std::vector<std::string>{"calculated", "exact"};
  return {"calculated", "exact", "approx"};  // local
}

struct Variable {
  std::string name, causality, variability, initial, unit;
  bool has_start = false;
  double start = 0.0, min = -INFINITY, max = INFINITY;
  unsigned vr = 0;
  std::size_t place = 0;  // 1-based, FMI 2.0's index
};

void check_variable(const Variable& v, const std::set<std::string>& units, bool v3, Rules& out) {
  const std::string who = "variable '" + v.name + "'";
  if (!allowed_combination(v.causality, v.variability))
    out.push_back(who + ": causality " + v.causality + " with variability " + v.variability +
                  " is not allowed");
  const auto initials = allowed_initial(v.causality, v.variability);
  const std::string initial = v.initial.empty() ? initials.front() : v.initial;
  if (!v.initial.empty() && (initials.front().empty() || std::find(initials.begin(), initials.end(),
                                                                   v.initial) == initials.end()))
    out.push_back(who + ": initial " + v.initial + " is not allowed for causality " + v.causality);
  const bool needs_start = initial == "exact" || initial == "approx" || v.causality == "input";
  const bool no_start = initial == "calculated" || v.causality == "independent";
  if (needs_start && !v.has_start) out.push_back(who + " needs a start value");
  if (no_start && v.has_start) out.push_back(who + " must not have a start value");
  if (!v.unit.empty() && units.count(v.unit) == 0)
    out.push_back(who + ": its unit '" + v.unit + "' is not declared in UnitDefinitions");
  if (v.min > v.max) out.push_back(who + ": min > max");
  if (v.has_start && (v.start < v.min || v.start > v.max))
    out.push_back(who + ": start outside [min, max]");
  if (v.has_start && !std::isfinite(v.start)) out.push_back(who + ": start is not finite");
  (void)v3;
}

Variable read_float(const pugi::xml_node& n, const pugi::xml_node& type, bool v3,
                    std::size_t place) {
  Variable v;
  v.name = n.attribute("name").value();
  v.causality = n.attribute("causality") ? n.attribute("causality").value() : "local";
  v.variability = n.attribute("variability") ? n.attribute("variability").value() : "continuous";
  v.initial = n.attribute("initial").value();
  v.vr = n.attribute("valueReference").as_uint();
  v.unit = type.attribute("unit").value();
  v.has_start = static_cast<bool>(type.attribute("start"));
  v.start = type.attribute("start").as_double();
  if (type.attribute("min")) v.min = type.attribute("min").as_double();
  if (type.attribute("max")) v.max = type.attribute("max").as_double();
  v.place = place;
  (void)v3;
  return v;
}

void check_units(const pugi::xml_node& defs, std::set<std::string>& units, Rules& out) {
  static const std::set<std::string> base = {"kg",  "m",  "s",   "A",      "K",
                                             "mol", "cd", "rad", "factor", "offset"};
  for (const pugi::xml_node u : defs.children("Unit")) {
    only_attributes(u, {"name"}, out);
    required(u, {"name"}, out);
    if (!units.insert(u.attribute("name").value()).second)
      out.push_back(std::string("the unit '") + u.attribute("name").value() +
                    "' is declared twice");
    for (const pugi::xml_node b : u.children("BaseUnit")) only_attributes(b, base, out);
  }
}

Rules fmi3(const pugi::xml_node& root) {
  Rules out;
  only_attributes(root,
                  {"fmiVersion", "modelName", "instantiationToken", "description", "author",
                   "version", "copyright", "license", "generationTool", "generationDateAndTime",
                   "variableNamingConvention"},
                  out);
  required(root, {"fmiVersion", "modelName", "instantiationToken"}, out);
  element_order(
      root,
      {"ModelExchange", "CoSimulation", "ScheduledExecution", "UnitDefinitions", "TypeDefinitions",
       "LogCategories", "DefaultExperiment", "ModelVariables", "ModelStructure", "Annotations"},
      out);
  const pugi::xml_node cs = root.child("CoSimulation");
  if (!cs) out.emplace_back("no <CoSimulation>");
  only_attributes(
      cs,
      {"modelIdentifier", "needsExecutionTool", "canBeInstantiatedOnlyOncePerProcess",
       "canGetAndSetFMUState", "canSerializeFMUState", "providesDirectionalDerivatives",
       "providesAdjointDerivatives", "providesPerElementDependencies",
       "canHandleVariableCommunicationStepSize", "fixedInternalStepSize",
       "maxOutputDerivativeOrder", "recommendedIntermediateInputSmoothness",
       "providesIntermediateUpdate", "mightReturnEarlyFromDoStep",
       "canReturnEarlyAfterIntermediateUpdate", "hasEventMode", "providesEvaluateDiscreteStates"},
      out);
  if (!is_c_identifier(cs.attribute("modelIdentifier").value()))
    out.emplace_back("modelIdentifier is not a C identifier");
  if (cs.attribute("fixedInternalStepSize") &&
      cs.attribute("fixedInternalStepSize").as_double() <= 0)
    out.emplace_back("fixedInternalStepSize is not positive");
  std::set<std::string> units;
  check_units(root.child("UnitDefinitions"), units, out);
  for (const pugi::xml_node c : root.child("LogCategories").children("Category"))
    only_attributes(c, {"name", "description"}, out);
  const pugi::xml_node de = root.child("DefaultExperiment");
  only_attributes(de, {"startTime", "stopTime", "tolerance", "stepSize"}, out);
  if (de && de.attribute("startTime").as_double() >= de.attribute("stopTime").as_double())
    out.emplace_back("DefaultExperiment: startTime is not before stopTime");

  std::vector<Variable> vars;
  std::set<std::string> names;
  std::set<unsigned> vrs;
  int independents = 0;
  std::size_t place = 0;
  for (const pugi::xml_node n : root.child("ModelVariables").children()) {
    ++place;
    if (std::string(n.name()) != "Float64") {
      out.push_back(std::string("<") + n.name() + "> is not expected (the FMU's are Float64)");
      continue;
    }
    only_attributes(n,
                    {"name",
                     "valueReference",
                     "description",
                     "causality",
                     "variability",
                     "canHandleMultipleSetPerTimeInstant",
                     "clocks",
                     "intermediateUpdate",
                     "previous",
                     "declaredType",
                     "initial",
                     "quantity",
                     "unit",
                     "displayUnit",
                     "relativeQuantity",
                     "unbounded",
                     "min",
                     "max",
                     "nominal",
                     "start",
                     "derivative",
                     "reinit"},
                    out);
    required(n, {"name", "valueReference"}, out);
    Variable v = read_float(n, n, true, place);
    if (!names.insert(v.name).second) out.push_back("the name '" + v.name + "' is used twice");
    if (!vrs.insert(v.vr).second)
      out.push_back("the value reference " + std::to_string(v.vr) + " is used twice");
    if (v.causality == "independent") ++independents;
    check_variable(v, units, true, out);
    vars.push_back(v);
  }
  if (independents != 1)
    out.push_back("there are " + std::to_string(independents) +
                  " independent variables: FMI 3.0 wants exactly one");

  // ModelStructure: every output once, in ModelVariables' order; the initial unknowns.
  std::vector<unsigned> outputs, listed, initial_listed, initial_wanted;
  for (const Variable& v : vars) {
    if (v.causality != "output") continue;
    outputs.push_back(v.vr);
    if (v.initial.empty() || v.initial == "calculated" || v.initial == "approx")
      initial_wanted.push_back(v.vr);
  }
  const pugi::xml_node ms = root.child("ModelStructure");
  for (const pugi::xml_node o : ms.children("Output")) {
    only_attributes(o, {"valueReference", "dependencies", "dependenciesKind"}, out);
    listed.push_back(o.attribute("valueReference").as_uint());
  }
  for (const pugi::xml_node o : ms.children("InitialUnknown")) {
    only_attributes(o, {"valueReference", "dependencies", "dependenciesKind"}, out);
    initial_listed.push_back(o.attribute("valueReference").as_uint());
  }
  if (listed != outputs)
    out.emplace_back("ModelStructure's Output elements are not the outputs in their order");
  if (initial_listed != initial_wanted)
    out.emplace_back(
        "ModelStructure's InitialUnknown elements are not the outputs with initial calculated");
  return out;
}

Rules fmi2(const pugi::xml_node& root) {
  Rules out;
  only_attributes(root,
                  {"fmiVersion", "modelName", "guid", "description", "author", "version",
                   "copyright", "license", "generationTool", "generationDateAndTime",
                   "variableNamingConvention", "numberOfEventIndicators"},
                  out);
  required(root, {"fmiVersion", "modelName", "guid"}, out);
  element_order(
      root,
      {"ModelExchange", "CoSimulation", "UnitDefinitions", "TypeDefinitions", "LogCategories",
       "DefaultExperiment", "VendorAnnotations", "ModelVariables", "ModelStructure"},
      out);
  const pugi::xml_node cs = root.child("CoSimulation");
  if (!cs) out.emplace_back("no <CoSimulation>");
  only_attributes(
      cs,
      {"modelIdentifier", "needsExecutionTool", "canHandleVariableCommunicationStepSize",
       "canInterpolateInputs", "maxOutputDerivativeOrder", "canRunAsynchronuously",
       "canBeInstantiatedOnlyOncePerProcess", "canNotUseMemoryManagementFunctions",
       "canGetAndSetFMUstate", "canSerializeFMUstate", "providesDirectionalDerivative"},
      out);
  if (!is_c_identifier(cs.attribute("modelIdentifier").value()))
    out.emplace_back("modelIdentifier is not a C identifier");
  std::set<std::string> units;
  check_units(root.child("UnitDefinitions"), units, out);
  std::vector<Variable> vars;
  std::set<std::string> names;
  std::set<unsigned> vrs;
  std::size_t place = 0;
  for (const pugi::xml_node n : root.child("ModelVariables").children("ScalarVariable")) {
    ++place;
    only_attributes(n,
                    {"name", "valueReference", "description", "causality", "variability", "initial",
                     "canHandleMultipleSetPerTimeInstant"},
                    out);
    required(n, {"name", "valueReference"}, out);
    const pugi::xml_node real = n.child("Real");
    if (!real) {
      out.push_back(std::string("variable '") + n.attribute("name").value() + "' is not Real");
      continue;
    }
    only_attributes(real,
                    {"declaredType", "quantity", "unit", "displayUnit", "relativeQuantity", "min",
                     "max", "nominal", "unbounded", "start", "derivative", "reinit"},
                    out);
    Variable v = read_float(n, real, false, place);
    if (!names.insert(v.name).second) out.push_back("the name '" + v.name + "' is used twice");
    if (!vrs.insert(v.vr).second)
      out.push_back("the value reference " + std::to_string(v.vr) + " is used twice");
    check_variable(v, units, false, out);
    vars.push_back(v);
  }
  std::vector<std::size_t> outputs, listed, initial_listed, initial_wanted;
  for (const Variable& v : vars) {
    if (v.causality != "output") continue;
    outputs.push_back(v.place);
    if (v.initial.empty() || v.initial == "calculated" || v.initial == "approx")
      initial_wanted.push_back(v.place);
  }
  const pugi::xml_node ms = root.child("ModelStructure");
  for (const pugi::xml_node u : ms.child("Outputs").children("Unknown"))
    listed.push_back(u.attribute("index").as_uint());
  for (const pugi::xml_node u : ms.child("InitialUnknowns").children("Unknown"))
    initial_listed.push_back(u.attribute("index").as_uint());
  if (listed != outputs)
    out.emplace_back("ModelStructure/Outputs does not list the outputs' indices in order");
  if (initial_listed != initial_wanted)
    out.emplace_back("ModelStructure/InitialUnknowns does not list the calculated outputs");
  return out;
}

}  // namespace

std::vector<std::string> model_description_violations(const pugi::xml_document& doc) {
  const pugi::xml_node root = doc.child("fmiModelDescription");
  if (!root) return {"no <fmiModelDescription> root"};
  const std::string version = root.attribute("fmiVersion").value();
  if (version == "3.0") return fmi3(root);
  if (version == "2.0") return fmi2(root);
  return {"fmiVersion is '" + version + "', neither 3.0 nor 2.0"};
}

}  // namespace mh::test
