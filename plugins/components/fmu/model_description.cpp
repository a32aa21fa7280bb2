#include "model_description.hpp"

#include <cstdlib>
#include <map>
#include <pugixml.hpp>
#include <stdexcept>

namespace fmu {
namespace {

bool flag(const pugi::xml_node& node, const char* name) {
  return node.attribute(name).as_bool(false);
}

uint32_t value_reference(const pugi::xml_node& node, const std::string& what) {
  const pugi::xml_attribute vr = node.attribute("valueReference");
  if (vr.empty()) throw std::runtime_error(what + " has no valueReference");
  return vr.as_uint();
}

}  // namespace

ModelDescription read_model_description(const std::string& folder) {
  const std::string path = folder + "/modelDescription.xml";
  pugi::xml_document document;
  const pugi::xml_parse_result parsed = document.load_file(path.c_str());
  if (!parsed) {
    if (parsed.status == pugi::status_file_not_found || parsed.status == pugi::status_io_error)
      throw std::runtime_error("it has no modelDescription.xml");
    throw std::runtime_error("its modelDescription.xml is not well-formed XML (" +
                             std::string(parsed.description()) + " at byte " +
                             std::to_string(parsed.offset) + ")");
  }
  const pugi::xml_node root = document.child("fmiModelDescription");
  if (root.empty()) throw std::runtime_error("its modelDescription.xml has no fmiModelDescription");
  ModelDescription d;
  d.fmi_version = root.attribute("fmiVersion").as_string();
  // 3.0 and its patch releases (3.0.1, 3.0.2) share the C interface.
  if (d.fmi_version != "3.0" && d.fmi_version.rfind("3.0.", 0) != 0)
    throw std::runtime_error(
        "it is an FMI " + (d.fmi_version.empty() ? std::string("(unknown)") : d.fmi_version) +
        " FMU (fmiVersion=\"" + d.fmi_version + "\"); only FMI 3.0 is imported");
  d.model_name = root.attribute("modelName").as_string();
  d.instantiation_token = root.attribute("instantiationToken").as_string();
  const pugi::xml_node me = root.child("ModelExchange");
  if (me.empty())
    throw std::runtime_error(root.child("CoSimulation").empty()
                                 ? "it offers no Model Exchange interface (no <ModelExchange>)"
                                 : "it is a Co-Simulation FMU only (no <ModelExchange>); only "
                                   "Model Exchange is imported");
  d.model_identifier = me.attribute("modelIdentifier").as_string();
  if (d.model_identifier.empty())
    throw std::runtime_error("its <ModelExchange> has no modelIdentifier");
  d.provides_directional_derivatives = flag(me, "providesDirectionalDerivatives");
  d.can_get_and_set_state = flag(me, "canGetAndSetFMUState");
  d.can_serialize_state = flag(me, "canSerializeFMUState");
  d.needs_completed_integrator_step = flag(me, "needsCompletedIntegratorStep");

  // Float64 variables by valueReference; other types are left at their start.
  std::map<uint32_t, Variable> float64;
  std::map<uint32_t, uint32_t> derivative_of;  // derivative's vr -> state's vr
  for (const pugi::xml_node v : root.child("ModelVariables").children()) {
    const std::string name = v.attribute("name").as_string();
    const std::string type = v.name();
    if (!v.child("Dimension").empty())
      throw std::runtime_error("its variable '" + name +
                               "' is an array (<Dimension>), which the import does not take");
    const std::string causality = v.attribute("causality").as_string("local");
    if (type != "Float64") {
      if (causality == "input" || causality == "output")
        throw std::runtime_error("its " + causality + " '" + name + "' is a " + type +
                                 "; only Float64 inputs and outputs are imported");
      continue;
    }
    Variable var;
    var.name = name;
    var.vr = value_reference(v, "its variable '" + name + "'");
    var.causality = causality;
    var.variability = v.attribute("variability").as_string("continuous");
    var.unit = v.attribute("unit").as_string();
    const pugi::xml_attribute start = v.attribute("start");
    var.has_start = !start.empty();
    var.start = start.as_double(0.0);
    if (!v.attribute("derivative").empty())
      derivative_of[var.vr] = v.attribute("derivative").as_uint();
    float64[var.vr] = var;
  }
  const pugi::xml_node structure = root.child("ModelStructure");
  for (const pugi::xml_node e : structure.children("ContinuousStateDerivative")) {
    const uint32_t dvr = value_reference(e, "a <ContinuousStateDerivative>");
    const auto of = derivative_of.find(dvr);
    if (of == derivative_of.end() || float64.count(of->second) == 0)
      throw std::runtime_error("its <ContinuousStateDerivative valueReference=\"" +
                               std::to_string(dvr) +
                               "\"> is not the derivative of a Float64 variable");
    d.states.push_back(float64[of->second]);
    d.derivatives.push_back(dvr);
  }
  for (const auto& entry : float64) {
    const Variable& v = entry.second;
    bool is_state = false;
    for (const Variable& s : d.states) is_state = is_state || s.vr == v.vr;
    if (v.causality == "input") d.inputs.push_back(v);
    if (v.causality == "output" && !is_state) d.outputs.push_back(v);
    if (v.causality == "parameter") d.parameters.push_back(v);
  }
  for (const pugi::xml_node e : structure.children("EventIndicator")) {
    (void)e;
    ++d.event_indicators;
  }
  // FMI 2.0 counted them in an attribute; a 3.0 file that still gives it is read too.
  const size_t counted = root.attribute("numberOfEventIndicators").as_ullong(0);
  if (counted > d.event_indicators) d.event_indicators = counted;
  return d;
}

}  // namespace fmu
