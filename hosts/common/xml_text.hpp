// Text made safe for XML content and attribute values: the report's SVG and
// HTML and an exported FMU's modelDescription.xml write it one way.
#pragma once

#include <string>

namespace mh::host {

std::string xml_escape(const std::string& text);

}  // namespace mh::host
