// The rules of a modelDescription.xml that the tests check an exported FMU
// against, from the FMI 3.0 and FMI 2.0 specifications and their schemas:
// the elements in the schema's order with only the schema's attributes,
// unique names and value references, the allowed combinations of
// causality, variability and initial, start where it is required and
// nowhere it is forbidden, every unit declared, and a ModelStructure that
// lists exactly the outputs. Written from the standard's text, not from
// monohydra's writer, so the writer cannot fool it.
#pragma once

#include <pugixml.hpp>
#include <string>
#include <vector>

namespace mh::test {

// Every rule `doc` breaks, one line each (empty: none). The version is the
// document's own fmiVersion.
std::vector<std::string> model_description_violations(const pugi::xml_document& doc);

}  // namespace mh::test
