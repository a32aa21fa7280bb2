// sensors: the instruments on the machine, each reading one result column
// (docs/model-format.md). Their column names are checked against the run's
// once it is set up (sensor_sampler.cpp): they depend on the plugins.
#include "parser.hpp"

namespace mh::model_file_detail {

std::vector<SensorSpec> Parser::sensors(const YAML::Node& node) const {
  if (!node.IsSequence())
    fail(node, "sensors",
         "expected a list of sensors ({name, measures, noise, rate, delay, bias}), got " +
             describe(node));
  std::vector<SensorSpec> list;
  std::map<std::string, SourceMark> seen;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string field = index_field("sensors", i);
    const MapView map(*this, node[i], field,
                      {"name", "measures", "noise", "rate", "delay", "bias"});
    SensorSpec s;
    s.mark = mark(node[i]);
    const YAML::Node name_node = map.require("name", "the sensor's name, e.g. crank_angle");
    s.name = name(name_node, map.field("name"));
    if (s.name == "t")
      fail(name_node, map.field("name"), "expected a name other than t (the time column's)");
    check_unique(seen, s.name, name_node, map.field("name"), "sensor");
    const YAML::Node measures = map.require("measures", "a result column, e.g. z1 or p2");
    s.measures = this->name(measures, map.field("measures"));
    s.measures_mark = mark(measures);
    if (auto noise = map.get("noise")) s.noise = non_negative(*noise, map.field("noise"));
    if (auto rate = map.get("rate")) {
      s.rate = positive(*rate, map.field("rate"));
      s.rate_mark = mark(*rate);
    }
    if (auto delay = map.get("delay")) {
      s.delay = non_negative(*delay, map.field("delay"));
      s.delay_mark = mark(*delay);
    }
    if (auto bias = map.get("bias")) s.bias = number(*bias, map.field("bias"));
    list.push_back(std::move(s));
  }
  return list;
}

}  // namespace mh::model_file_detail
