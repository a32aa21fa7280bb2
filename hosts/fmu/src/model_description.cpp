#include "model_description.hpp"

#include <cstdio>
#include <ctime>
#include <set>
#include <sstream>

#include "monohydra/cpp/number_text.hpp"
#include "si_unit.hpp"
#include "xml_text.hpp"

namespace mh::fmu {

using monohydra::exact_number;  // the shortest text that reads back as the same double

namespace {

const char* causality_name(Causality c) {
  switch (c) {
    case Causality::independent:
      return "independent";
    case Causality::output:
      return "output";
    case Causality::input:
      return "input";
    case Causality::parameter:
      return "parameter";
  }
  return "local";
}

// The predefined log categories the FMU uses (FMI 3.0, 2.4.5).
void log_categories(std::ostream& out) {
  out << "  <LogCategories>\n"
         "    <Category name=\"logStatusWarning\" description=\"the engine's warnings\"/>\n"
         "    <Category name=\"logStatusError\" description=\"why a call failed\"/>\n"
         "    <Category name=\"logStatusFatal\" description=\"why the instance cannot go on\"/>\n"
         "  </LogCategories>\n";
}

void unit_definitions(std::ostream& out, const std::vector<FmuVariable>& variables) {
  std::set<std::string> units;
  for (const FmuVariable& v : variables)
    if (!v.unit.empty()) units.insert(v.unit);
  if (units.empty()) return;
  out << "  <UnitDefinitions>\n";
  for (const std::string& u : units) {
    out << "    <Unit name=\"" << host::xml_escape(u) << "\"";
    const auto base = base_unit(u);
    if (!base) {
      out << "/>\n";
      continue;
    }
    out << ">\n      <BaseUnit";
    for (std::size_t k = 0; k < base->size(); ++k)
      if ((*base)[k] != 0) out << ' ' << kBaseUnitNames[k] << "=\"" << (*base)[k] << '"';
    out << "/>\n    </Unit>\n";
  }
  out << "  </UnitDefinitions>\n";
}

void default_experiment(std::ostream& out, const Description& d) {
  out << "  <DefaultExperiment startTime=\"0\" stopTime=\"" << exact_number(d.t_end)
      << "\" stepSize=\"" << exact_number(d.dt) << "\"/>\n";
}

// The attributes a variable's kind decides (FMI 3.0 Table 18 / FMI 2.0 p. 49:
// only allowed causality, variability and initial combinations).
std::string variability(const FmuVariable& v) {
  if (v.causality != Causality::parameter) return "continuous";
  return v.tunable ? "tunable" : "fixed";
}

std::string header_attributes(const Description& d) {
  char when[32];
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  std::strftime(when, sizeof(when), "%Y-%m-%dT%H:%M:%SZ", &utc);
  std::ostringstream out;
  out << " modelName=\"" << host::xml_escape(d.model_name) << "\" description=\""
      << host::xml_escape(d.model_name)
      << ", a hydraulically actuated multibody model exported by monohydra\" generationTool=\""
      << host::xml_escape(d.generation_tool) << "\" generationDateAndTime=\"" << when
      << "\" variableNamingConvention=\"flat\"";
  return out.str();
}

std::string fmi3(const Description& d) {
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<fmiModelDescription fmiVersion=\"3.0\""
      << header_attributes(d) << " instantiationToken=\"" << host::xml_escape(d.token) << "\">\n";
  out << "  <CoSimulation modelIdentifier=\"" << host::xml_escape(d.model_identifier)
      << "\" canHandleVariableCommunicationStepSize=\"true\" fixedInternalStepSize=\""
      << exact_number(d.dt)
      << "\" canGetAndSetFMUState=\"true\" canSerializeFMUState=\"true\""
         " canBeInstantiatedOnlyOncePerProcess=\"false\" hasEventMode=\"false\""
         " providesIntermediateUpdate=\"false\" "
         "canReturnEarlyAfterIntermediateUpdate=\"false\"/>\n";
  unit_definitions(out, d.variables);
  log_categories(out);
  default_experiment(out, d);
  out << "  <ModelVariables>\n";
  for (const FmuVariable& v : d.variables) {
    out << "    <Float64 name=\"" << host::xml_escape(v.name) << "\" valueReference=\""
        << v.value_reference << "\" description=\"" << host::xml_escape(v.description)
        << "\" causality=\"" << causality_name(v.causality) << "\" variability=\"" << variability(v)
        << '"';
    if (v.causality == Causality::parameter) out << " initial=\"exact\"";
    if (!v.unit.empty()) out << " unit=\"" << host::xml_escape(v.unit) << '"';
    if (v.min <= v.max)
      out << " min=\"" << exact_number(v.min) << "\" max=\"" << exact_number(v.max) << '"';
    if (v.causality == Causality::parameter || v.causality == Causality::input)
      out << " start=\"" << exact_number(v.start) << '"';
    out << "/>\n";
  }
  out << "  </ModelVariables>\n  <ModelStructure>\n";
  for (const FmuVariable& v : d.variables)
    if (v.causality == Causality::output)
      out << "    <Output valueReference=\"" << v.value_reference << "\"/>\n";
  for (const FmuVariable& v : d.variables)
    if (v.causality == Causality::output)
      out << "    <InitialUnknown valueReference=\"" << v.value_reference << "\"/>\n";
  out << "  </ModelStructure>\n</fmiModelDescription>\n";
  return out.str();
}

// FMI 2.0 has no required independent variable: time is left out, and
// ModelStructure refers to variables by their 1-based place in ModelVariables.
std::string fmi2(const Description& d) {
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<fmiModelDescription fmiVersion=\"2.0\""
      << header_attributes(d) << " guid=\"" << host::xml_escape(d.token)
      << "\" numberOfEventIndicators=\"0\">\n";
  out << "  <CoSimulation modelIdentifier=\"" << host::xml_escape(d.model_identifier)
      << "\" canHandleVariableCommunicationStepSize=\"true\" canGetAndSetFMUstate=\"true\""
         " canSerializeFMUstate=\"true\" canNotUseMemoryManagementFunctions=\"true\"/>\n";
  unit_definitions(out, d.variables);
  log_categories(out);
  default_experiment(out, d);
  out << "  <ModelVariables>\n";
  std::vector<std::size_t> outputs;
  std::size_t place = 0;
  for (const FmuVariable& v : d.variables) {
    if (v.causality == Causality::independent) continue;
    ++place;
    if (v.causality == Causality::output) outputs.push_back(place);
    out << "    <ScalarVariable name=\"" << host::xml_escape(v.name) << "\" valueReference=\""
        << v.value_reference << "\" description=\"" << host::xml_escape(v.description)
        << "\" causality=\"" << causality_name(v.causality) << "\" variability=\"" << variability(v)
        << '"';
    if (v.causality == Causality::parameter) out << " initial=\"exact\"";
    if (v.causality == Causality::output) out << " initial=\"calculated\"";
    out << ">\n      <Real";
    if (!v.unit.empty()) out << " unit=\"" << host::xml_escape(v.unit) << '"';
    if (v.min <= v.max)
      out << " min=\"" << exact_number(v.min) << "\" max=\"" << exact_number(v.max) << '"';
    if (v.causality == Causality::parameter || v.causality == Causality::input)
      out << " start=\"" << exact_number(v.start) << '"';
    out << "/>\n    </ScalarVariable>\n";
  }
  out << "  </ModelVariables>\n  <ModelStructure>\n    <Outputs>\n";
  for (std::size_t k : outputs) out << "      <Unknown index=\"" << k << "\"/>\n";
  out << "    </Outputs>\n    <InitialUnknowns>\n";
  for (std::size_t k : outputs) out << "      <Unknown index=\"" << k << "\"/>\n";
  out << "    </InitialUnknowns>\n  </ModelStructure>\n</fmiModelDescription>\n";
  return out.str();
}

}  // namespace

std::string model_description_xml(const Description& d) {
  return d.fmi_version == 2 ? fmi2(d) : fmi3(d);
}

}  // namespace mh::fmu
