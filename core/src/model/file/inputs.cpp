// inputs: the model's named external signals (docs/model-format.md), each
// with its unit, range, what happens to a value outside it, and its initial
// value or a time table it follows until something sets it.
#include "model/time_table.hpp"
#include "parser.hpp"

namespace mh::model_file_detail {

std::vector<InputSpec> Parser::inputs(const YAML::Node& node) const {
  if (!node.IsSequence())
    fail(
        node, "inputs",
        "expected a list of inputs ({name, unit, range, initial or table}), got " + describe(node));
  std::vector<InputSpec> list;
  std::map<std::string, SourceMark> seen;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string field = index_field("inputs", i);
    const MapView map(*this, node[i], field,
                      {"name", "unit", "range", "out_of_range", "initial", "table"});
    InputSpec in;
    in.mark = mark(node[i]);
    const YAML::Node name_node = map.require("name", "the input's name, e.g. boom_lever");
    in.name = name(name_node, map.field("name"));
    check_unique(seen, in.name, name_node, map.field("name"), "input");
    if (auto unit = map.get("unit")) in.unit = string(*unit, map.field("unit"));
    if (auto range = map.get("range")) {
      if (!range->IsSequence() || range->size() != 2)
        fail(*range, map.field("range"), "expected [min, max], got " + describe(*range));
      in.min = number((*range)[0], index_field(map.field("range"), 0));
      in.max = number((*range)[1], index_field(map.field("range"), 1));
      if (!(in.min < in.max))
        fail(*range, map.field("range"),
             "expected min < max, got [" + format_number(in.min) + ", " + format_number(in.max) +
                 "]");
    }
    if (auto policy = map.get("out_of_range")) {
      const std::string text = string(*policy, map.field("out_of_range"));
      if (text != "refuse" && text != "clamp")
        fail(*policy, map.field("out_of_range"),
             "expected refuse or clamp (a value outside the range), got '" + text + "'");
      in.clamp = text == "clamp";
    }
    const auto initial = map.get("initial");
    const auto table = map.get("table");
    if (initial && table)
      fail(*initial, map.field("initial"),
           "expected initial or table, not both (a table gives the value at t = 0)");
    if (initial) in.initial = number(*initial, map.field("initial"));
    if (table) {
      const OptionValue rows = option(*table, map.field("table"));
      TimeTable check;
      std::string error;
      if (rows.kind != OptionValue::Kind::table || rows.columns != 2 ||
          !check.assign(rows.table.data(), static_cast<uint32_t>(rows.rows), error))
        fail(*table, map.field("table"),
             "expected " + (error.empty() ? std::string("rows [t (s), value]") : error) + ", got " +
                 describe(*table));
      in.table = rows.table;
      in.initial = check.value(0.0);
      for (size_t r = 0; in.min < in.max && !in.clamp && r < static_cast<size_t>(rows.rows); ++r) {
        const double v = rows.table[2 * r + 1];
        if (!(v >= in.min && v <= in.max))
          fail((*table)[static_cast<size_t>(r)],
               index_field(map.field("table"), static_cast<size_t>(r)),
               "expected a value within the range [" + format_number(in.min) + ", " +
                   format_number(in.max) + "] (out_of_range: refuse), got " + format_number(v));
      }
    }
    const bool ranged = in.min < in.max;
    if (ranged && !in.clamp && !(in.initial >= in.min && in.initial <= in.max))
      fail(table     ? *table
           : initial ? *initial
                     : node[i],
           map.field(table ? "table" : "initial"),
           "expected an initial value within the range [" + format_number(in.min) + ", " +
               format_number(in.max) + "], got " + format_number(in.initial));
    list.push_back(std::move(in));
  }
  return list;
}

}  // namespace mh::model_file_detail
